// A one-line progress report on a terminal: step, time, rate and remaining time.
#pragma once

#include <chrono>
#include <cstdint>

#include "silt/state.hpp"

namespace silt::cli {

class Progress {
 public:
  // The rate is in grain-steps per second, or in cell-steps of a grid without grains (a fluid's).
  Progress(bool enabled, int64_t first_step, int64_t total_steps, int64_t n_grains, int64_t n_cells = 0);
  void update(const State& s);
  void finish();

 private:
  bool enabled_;
  int64_t first_, total_, n_;
  const char* unit_;
  std::chrono::steady_clock::time_point t0_;
  bool drawn_ = false;
};

}  // namespace silt::cli
