// The shear module (silt/module.hpp).
#pragma once

#include "silt/module.hpp"

namespace silt::shear {

const ModuleSpec& module();

}  // namespace silt::shear
