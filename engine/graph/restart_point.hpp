// The restart point of the last-good-state replay (Simulation keeps one, taken every
// limits.check_every steps): a copy of the State, except that of the per-pair forces and springs
// it keeps only those of the pairs that hold one, and pair_i not at all (it follows from
// nbr_start). In a dense bed most listed pairs do not touch, so this is well under a full copy;
// give() returns the State taken, bit for bit.
#pragma once

#include <cstdint>
#include <vector>

#include "silt/state.hpp"

namespace silt::graph {

class RestartPoint {
 public:
  // Copy s (left as it was).
  void take(State& s);
  // The State taken.
  State give() const;
  int64_t step() const { return base_.step; }
  size_t bytes() const {
    return state_bytes(base_) + held_.capacity() * 4 + (held_f_.capacity() + held_hist_.capacity()) * 8;
  }

 private:
  State base_;                  // s without pair_i, pair_f and pair_hist
  std::vector<int32_t> held_;   // pairs with a non-zero force or spring (any bit set)
  std::vector<double> held_f_;  // their forces and springs, D per pair
  std::vector<double> held_hist_;
};

}  // namespace silt::graph
