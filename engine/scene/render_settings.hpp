// Reading [render] into Model::render.
#pragma once

#include "silt/model.hpp"

namespace silt::scene {

void read_render_settings(const SceneDesc& d, Model& m);

}  // namespace silt::scene
