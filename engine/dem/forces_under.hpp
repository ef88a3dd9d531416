// The parameters the forces a state holds were made under. A value steered between steps (a
// friction, a material, a drag's viscosity), or a state given to a model compiled with other
// values, leaves forces of the old parameters in the state, which the next half kick would use:
// the change would enter the dynamics half a step late, and force observables would show the old
// forces. The DEM keeps the parameters of every force on the grains with the forces it leaves
// (dem_forces_under: the first state's, and those made again); under a model whose differ, the
// forces are made again before the step (graph::Phase::kResolve, engine/graph/dem_stages.cpp).
#pragma once

#include <vector>

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::dem {

// The DEM's own: the contact laws between grains and with the walls, the materials, the walls'
// friction.
std::vector<double> contact_parameters(const Model& m);
// Those of every module on (ModuleSpec::force_parameters), in module order.
std::vector<double> force_parameters(const Model& m);
FieldId forces_under_field();
// Whether the state's forces were made under other parameters than m's. An empty record (a
// checkpoint written before it was kept): no, the forces are used as they are.
bool forces_under_other(const Model& m, const State& s);
// () => (dem_forces_under): the forces of the state are m's.
void record_forces_under(const Model& m, State& s);

}  // namespace silt::dem
