// How the fluid's sweeps share a grid's rows among the threads. A sweep of a small grid takes
// microseconds, its fields fit in the cores' own caches, and a share of rows that moves to the
// other thread from one sweep to the next costs more than it balances: a grid of at most
// kPinnedCells cells gives each thread the same rows at every sweep (parallel_for_pinned). A
// larger one is shared as the threads come free, which relieves a core the host slows down.
// Measured with `build/bench/fluid --only throughput` (the Taylor-Green vortex on two threads,
// two runs each, 2026-12-02): pinned shares made 32^3 1.17 to 1.32 times as fast and 64^3 1.03
// to 1.20 times, and 256^3 0.73 to 0.94 times; 2D grids up to 1024^2 the same within the noise.
// Which thread sweeps which rows changes no result: the rows' outputs are disjoint.
#pragma once

#include <cstdint>

#include "core/parallel.hpp"

namespace silt::fluid {

constexpr int64_t kPinnedCells = int64_t{1} << 18;  // 64^3, 512^2

// f(begin, end) over [0, n) in blocks of at least `grain`, for a sweep of a grid of `cells`.
template <class F>
void sweep_for(int64_t cells, int64_t n, int64_t grain, F&& f) {
  if (cells <= kPinnedCells) parallel_for_pinned(n, grain, f);
  else parallel_for(n, grain, f);
}

}  // namespace silt::fluid
