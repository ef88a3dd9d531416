// The paste's observables (names of INTERFACE.md): the viscous number, the friction
// mobilisation, the contact and lubrication shares of the pressure, the effective viscosity and
// the solver's counts.
#pragma once

#include <vector>

#include "silt/observables.hpp"

namespace silt::paste {

std::vector<ObservableSpec> paste_observables();

// <|F_T| / F_N> over the grain-grain contacts (Peyneau 2009 sec. 2.3.1), 0 without contacts.
double friction_mobilisation(const State& s);

}  // namespace silt::paste
