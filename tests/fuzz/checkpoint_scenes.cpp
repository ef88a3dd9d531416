#include "checkpoint_scenes.hpp"

#include "fuzz_support.hpp"

namespace silt::fuzz {

const std::vector<CheckpointScene>& checkpoint_scenes() {
  static const std::vector<CheckpointScene> scenes = {
      {"collision_normal", "scenes/collision_normal.toml", {}, {0, 250}},  // in contact from about step 200
      {"bounce_dry", "scenes/bounce_dry.toml", {}, {10}},
      {"bounce_drag", "scenes/bounce_dry.toml", {{"drag.viscosity", "1.8e-5"}}, {10}},
      {"pack_2d", "scenes/pack_2d.toml", {{"grains[0].count", "40"}, {"domain.hi", "[8.0, 8.0]"}}, {200}},
      {"shear2d", "scenes/shear2d_dry.toml", {{"grains[0].count", "60"}, {"prepare.compress", "false"}}, {100}},
      {"shear3d",
       "scenes/shear3d_frictionless.toml",
       {{"grains[0].count", "40"}, {"prepare.compress", "false"}},
       {100}},
      // The paste: an isotropic box at imposed pressure, and Lees-Edwards shear at a viscous number.
      {"paste_iso", "scenes/paste_iso.toml", {{"grains[0].count", "40"}}, {20}},
      {"paste_shear", "scenes/paste_shear.toml", {{"grains[0].count", "80"}}, {20}},
      // The resolved fluid: a lid-driven cavity on a small grid.
      {"cavity_2d", "scenes/cavity_2d.toml", {{"fluid.cells", "[16, 16]"}}, {20}},
  };
  return scenes;
}

Model compile_scene(const CheckpointScene& s) { return compile(load_scene_file(source_path(s.file), s.overrides)); }

}  // namespace silt::fuzz
