// A grain that has left the domain through a face that neither a wall nor periodicity closes: it
// falls for ever under gravity, or leaves a pressure-controlled box to collapse, and the failure
// that follows (a runaway kinetic energy, a box length below the interaction range) is of that.
#pragma once

#include <string>

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::dem {

// "grain ID left the domain through its z_lo face (z = -19.6 m), which neither a wall nor
// periodicity closes", for the first free grain whose centre is more than its radius outside the
// domain along an axis that is not periodic; "" when every grain is in.
std::string escaped_grain(const Model& m, const State& s);

// The advice that follows it in a failure's message.
inline constexpr const char* kEscapeAdvice =
    "close that face with a wall ([[walls]]), make the axis periodic (domain.periodic), or make the domain larger";

}  // namespace silt::dem
