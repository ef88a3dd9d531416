// The scale of the equilibrium criterion (Simulation::is_static, Peyneau 2009 sec. 2.3.2), for the
// stages that must agree with it.
#pragma once

#include "silt/model.hpp"

namespace silt {

// The largest net force on a grain that a static packing may keep: run.static_force_tol times
// a^(d-1) P (a the largest diameter, P box.pressure); 0 without an imposed pressure.
double static_force(const Model& m);

}  // namespace silt
