// The core's stages: the step's time step first (advance_clock, last, is added by
// build_stage_list once every module is in).
#include "graph/adders.hpp"

namespace silt::graph {

void add_core_stages(GraphBuilder& b) {
  if (b.phase() != Phase::kStep) return;
  // () => (dt). Fixed: the scene's (steerable) time step. A module that needs another (the CFL
  // number of a fluid, the adaptive step of a paste) will choose it here.
  b.light(b.add("choose_dt", [](const Model& m, State& s) { s.dt = m.dt; }, {}, {fid::dt}));
}

}  // namespace silt::graph
