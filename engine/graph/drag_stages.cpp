// The drag's stage: after the neighbour update (which may renumber the grains), its force and
// torque join the kick's sum.
#include "drag/drag.hpp"
#include "graph/graph_builder.hpp"

namespace silt::graph {

void add_drag_stages(GraphBuilder& b) {
  const FieldId f = find_field("particle_f_drag")->id, t = find_field("particle_t_drag")->id;
  const int drag = b.add("drag_forces", [f, t](const Model& m, State& s) { drag::drag_forces(m, s, f, t); },
                         {fid::particle_v, fid::particle_w, fid::particle_r, fid::particle_frozen}, {f, t});
  // (the forces made again for a state given or steered follow no neighbour update: Phase::kResolve)
  if (const int nbr = b.find("update_neighbors"); nbr >= 0)
    b.after(drag, nbr, "a rebuild may renumber the grains (cell order)");
  b.add_force({f, t}, drag);
}

}  // namespace silt::graph
