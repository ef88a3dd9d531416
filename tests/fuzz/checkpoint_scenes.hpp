// The scenes whose checkpoints seed the checkpoint target, one per kind of state: 3D grains in
// contact, a wall, a stress-controlled 2D box, Lees-Edwards shear in 2D and 3D, a module's own
// fields (drag), a paste at imposed pressure and sheared, a resolved fluid. Shipped scenes, made small where they are large: the target reads a file at some
// microseconds a hundred bytes under the sanitizers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "silt/model.hpp"
#include "silt/scene.hpp"

namespace silt::fuzz {

struct CheckpointScene {
  std::string name;
  std::string file;  // in the source tree
  std::vector<Override> overrides;
  std::vector<int64_t> steps;  // a checkpoint after each of these numbers of steps
};

const std::vector<CheckpointScene>& checkpoint_scenes();
Model compile_scene(const CheckpointScene& s);

}  // namespace silt::fuzz
