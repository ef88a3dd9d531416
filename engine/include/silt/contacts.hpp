// The contact network of a state: every touching pair of grains, for measurements, pictures and
// files (stress, coordination, force chains, VTK).
#pragma once

#include <array>
#include <vector>

#include "silt/state.hpp"

namespace silt {

struct Contact {
  int64_t i = 0, j = 0;       // grain indices
  int64_t pair = 0;           // index in the pair arrays
  std::array<double, 3> d{};  // x_i - x_j, nearest periodic image (z = 0 in 2D)
  double dist = 0;            // |d|
  std::array<double, 3> f{};  // force on i from j
  double fn = 0;              // normal force f . d / |d| (> 0 repulsive)
};

// Touching pairs (|d| < r_i + r_j), in pair order.
std::vector<Contact> touching_contacts(const State& s);

}  // namespace silt
