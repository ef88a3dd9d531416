// The identity of the system a checkpoint belongs to (Model::scene_hash).
#include "core/rng.hpp"
#include "silt/model.hpp"

namespace silt {

uint64_t system_fingerprint(const Model& m, const std::vector<uint8_t>& frozen) {
  uint64_t h = fnv1a(&m.dim, sizeof m.dim);
  h = fnv1a(&m.n_grains, sizeof m.n_grains, h);
  h = fnv1a(m.box.periodic.data(), sizeof(bool) * 3, h);
  const size_t nw = m.walls.size();
  h = fnv1a(&nw, sizeof nw, h);
  h = fnv1a(m.init.radius.data(), sizeof(double) * m.init.radius.size(), h);
  h = fnv1a(m.init.mass.data(), sizeof(double) * m.init.mass.size(), h);
  h = fnv1a(frozen.data(), frozen.size(), h);
  h = fnv1a(m.init.group.data(), sizeof(int32_t) * m.init.group.size(), h);
  return h;
}

}  // namespace silt
