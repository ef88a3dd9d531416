// A reference for two-thread speed-ups on a given machine: work that shares nothing between
// threads and touches no memory beyond the first-level caches, cut into fork-joins as often as a
// simulation step joins its stages. Timed right next to a program, its two-thread / one-thread
// ratio is what the machine gives at that moment (close to 2 on two free cores); a program that
// scales less than it loses time to itself, one that scales as much loses it to the machine.
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bench_util.hpp"

namespace silt::bench {

class ReferenceLoop {
 public:
  // `joins` fork-joins per step over `items` items.
  ReferenceLoop(int64_t items, int joins) : x_(items, 1.0), joins_(joins) {}

  // Sets the work per item so that one step takes `step_s` seconds on one thread.
  void calibrate(double step_s) {
    rounds_ = 16;
    const double t = seconds(1, 50) / 50;
    rounds_ = std::max<int64_t>(1, static_cast<int64_t>(rounds_ * step_s / t));
  }

  // Wall time of `steps` steps on `threads` threads.
  double seconds(int threads, int64_t steps) {
    tbb::task_arena arena(threads);
    const double t0 = now_s();
    arena.execute([&] {
      for (int64_t s = 0; s < steps; ++s)
        for (int j = 0; j < joins_; ++j)
          tbb::parallel_for(tbb::blocked_range<int64_t>(0, static_cast<int64_t>(x_.size()), 512),
                            [&](const tbb::blocked_range<int64_t>& r) {
                              for (int64_t i = r.begin(); i < r.end(); ++i) {
                                double v = x_[i];
                                for (int64_t k = 0; k < rounds_; ++k) v = v * 0.999999 + 1e-6;
                                x_[i] = v;
                              }
                            });
    });
    return now_s() - t0;
  }

 private:
  std::vector<double> x_;
  int joins_;
  int64_t rounds_ = 16;
};

// The other reference: a loop with the memory traffic of silt's kick (per grain, a force, a
// torque, an inverse mass and an inverse inertia read, a velocity and an angular velocity
// updated: 160 bytes) over as many grains as the scene, one fork-join per sweep. Its two-thread
// / one-thread ratio is what this machine's memory gives a grain pass at that moment: on a
// virtual machine whose two cores share the memory with other guests it can stay near 1.4
// while compute-bound work doubles.
class StreamLoop {
 public:
  explicit StreamLoop(int64_t grains)
      : f_(3 * grains, 1e-3),
        t_(3 * grains, 1e-3),
        v_(3 * grains, 0.0),
        w_(3 * grains, 0.0),
        im_(grains, 1.0),
        ii_(grains, 1.0) {}

  // Wall time of `sweeps` sweeps on `threads` threads.
  double seconds(int threads, int64_t sweeps) {
    tbb::task_arena arena(threads);
    const int64_t n = static_cast<int64_t>(im_.size());
    const double t0 = now_s();
    arena.execute([&] {
      for (int64_t s = 0; s < sweeps; ++s)
        tbb::parallel_for(tbb::blocked_range<int64_t>(0, n, 1024), [&](const tbb::blocked_range<int64_t>& r) {
          for (int64_t i = r.begin(); i < r.end(); ++i)
            for (int k = 0; k < 3; ++k) {
              v_[3 * i + k] += 5e-5 * f_[3 * i + k] * im_[i];
              w_[3 * i + k] += 5e-5 * t_[3 * i + k] * ii_[i];
            }
        });
    });
    return now_s() - t0;
  }

 private:
  std::vector<double> f_, t_, v_, w_, im_, ii_;
};

}  // namespace silt::bench
