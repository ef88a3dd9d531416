#include "shell/progress.hpp"

#include <cstdio>

namespace silt::cli {

Progress::Progress(bool enabled, int64_t first_step, int64_t total_steps, int64_t n_grains, int64_t n_cells)
    : enabled_(enabled),
      first_(first_step),
      total_(total_steps),
      n_(n_grains > 0 || n_cells <= 0 ? n_grains : n_cells),
      unit_(n_grains > 0 || n_cells <= 0 ? "grain-steps/s" : "cell-steps/s"),
      t0_(std::chrono::steady_clock::now()) {}

void Progress::update(const State& s) {
  if (!enabled_) return;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  const int64_t done = s.step - first_;
  const double rate = el > 0 ? done / el : 0;
  const double eta = rate > 0 && total_ > 0 ? (total_ - done) / rate : 0;
  if (total_ > 0)
    std::fprintf(stderr, "\r  step %lld/%lld (%5.1f%%)  t = %-10.4g  %.3g %s  eta %02d:%02d  ",
                 static_cast<long long>(s.step), static_cast<long long>(first_ + total_), 100.0 * done / total_, s.t,
                 rate * n_, unit_, static_cast<int>(eta) / 60, static_cast<int>(eta) % 60);
  else
    std::fprintf(stderr, "\r  step %lld  t = %-10.4g  %.3g %s  (Ctrl-C pauses)  ", static_cast<long long>(s.step), s.t,
                 rate * n_, unit_);
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::finish() {
  if (drawn_) std::fprintf(stderr, "\n");
  drawn_ = false;
}

}  // namespace silt::cli
