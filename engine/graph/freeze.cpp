// Simulation::freeze: grains made frozen between two steps.
#include <algorithm>
#include <stdexcept>

#include "core/workspace.hpp"
#include "dem/module.hpp"
#include "silt/simulation.hpp"

namespace silt {
namespace {

// Grain `id` frozen in the model's grains, and among those `freeze` froze (which a recompile keeps).
void mark_frozen(Model& m, int64_t id) {
  m.init.frozen[id] = 1;
  if (m.init.frozen_by_freeze.empty()) m.init.frozen_by_freeze.assign(m.init.frozen.size(), 0);
  m.init.frozen_by_freeze[id] = 1;
}

}  // namespace

int64_t Simulation::freeze(int axis, bool below, double value) {
  Model& m = model_;
  State& s = state_;
  if (axis < 0 || axis >= m.dim) throw std::invalid_argument("no axis " + std::to_string(axis) + " in this scene");
  if (m.deforming_box()) throw std::invalid_argument("a deforming box (box.pressure, shear) cannot hold frozen grains");
  prepare();
  const int D = m.dim, R = m.rot;
  int64_t count = 0;
  for (int64_t i = 0; i < s.n; ++i) {
    if (s.particle_frozen[i]) continue;
    const double x = s.particle_x[D * i + axis];
    if (below ? !(x < value) : !(x > value)) continue;
    s.particle_frozen[i] = 1;
    s.particle_inv_m[i] = 0;
    s.particle_inv_i[i] = 0;
    for (int k = 0; k < D; ++k) s.particle_v[D * i + k] = 0;
    for (int k = 0; k < R; ++k) s.particle_w[R * i + k] = 0;
    mark_frozen(m, s.particle_id[i]);
    ++count;
  }
  if (count == 0) return 0;
  dem::refresh_frozen(m);
  // Pairs of two frozen grains leave the list at the next build; the restart point and the
  // workspaces start from this state.
  s.nbr_valid = false;
  restore(State(s));
  return count;
}

int64_t Simulation::freeze_grains(const std::vector<uint8_t>& by_id) {
  Model& m = model_;
  if (by_id.size() != m.init.frozen.size()) throw std::invalid_argument("freeze_grains: one flag per grain expected");
  const bool any = std::find(by_id.begin(), by_id.end(), 1) != by_id.end();
  if (any && m.deforming_box())
    throw std::invalid_argument("a deforming box (box.pressure, shear) cannot hold frozen grains");
  int64_t count = 0;
  for (size_t id = 0; id < by_id.size(); ++id)
    if (by_id[id] && !m.init.frozen[id]) {
      mark_frozen(m, static_cast<int64_t>(id));
      ++count;
    }
  if (count) dem::refresh_frozen(m);
  return count;
}

}  // namespace silt
