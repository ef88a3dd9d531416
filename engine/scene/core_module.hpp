// The modules of scene/: the core (time, box, gravity, run, outputs) and the render settings.
#pragma once

#include "silt/module.hpp"

namespace silt::scene {

const ModuleSpec& core_module();
const ModuleSpec& render_module();

}  // namespace silt::scene
