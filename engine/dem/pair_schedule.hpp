// A conflict-free order for the pair loop, so that every pair adds its force to both grains
// directly (no per-pair storage and no second pass to gather it) and the sums do not depend on
// the number of threads.
//
// The rows of the half list are cut into fixed blocks of Model-independent size. Two blocks
// conflict when some grain receives a force from pairs of both (a grain is written by the block
// of its own row and by the blocks of the rows that list it). Blocks are coloured greedily in
// order; the blocks of one colour write disjoint grains and run in parallel, the colours one
// after the other. Each grain thus receives its pair forces in an order fixed by the list alone:
// by colour, then by row, then by position in the row.
//
// The colours need not end in a barrier: run_pair_schedule starts each block as soon as the
// blocks before it that write the same grains have run (PairSchedule::after), which keeps that
// order and lets a thread go on with other blocks while one block waits on a busy core.
//
// With grains in cell order (see neighbor_list.cpp) a block's partners lie within about one
// layer of cells, and a few colours suffice; without that order the schedule stays correct and
// only runs more serially.
#pragma once

#include <tbb/parallel_for_each.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <vector>

#include "silt/state.hpp"

namespace silt::dem {

// A conflict-free order of the pair loop's blocks of rows.
struct PairSchedule {
  static constexpr int64_t kBlock = 1024;  // rows per block
  std::vector<int32_t> blocks;             // block indices, grouped by colour
  std::vector<int32_t> colour_start;       // colour c holds blocks[colour_start[c] .. colour_start[c + 1])
  int colours() const { return static_cast<int>(colour_start.size()) - 1; }
  // The same order as a graph: block b may run once its n_before[b] predecessors have run (the
  // blocks of earlier colours that write a grain it writes, the nearest for each such grain); its
  // successors are after[after_start[b] .. after_start[b + 1]). roots: the blocks without
  // predecessors. Block b is the first to write the grains of the blocks
  // clears[clears_start[b] .. clears_start[b + 1]).
  std::vector<int32_t> n_before, after_start, after, roots, clears_start, clears;
  std::vector<int32_t> waiting;  // predecessors not yet run, during a pass
};

// The schedule of a half list in CSR form (row i holds its partners j).
PairSchedule build_pair_schedule(int64_t n, const std::vector<int32_t>& nbr_start, const std::vector<int32_t>& pair_j);

// body(b) for every block b of the schedule, each after the blocks before it in the schedule's
// order that write the same grains, and in parallel with the others.
template <class F>
void run_pair_schedule(PairSchedule& s, F&& body) {
  if (tbb::this_task_arena::max_concurrency() == 1 || s.blocks.size() <= 1) {
    for (int32_t b : s.blocks) body(b);
    return;
  }
  std::copy(s.n_before.begin(), s.n_before.end(), s.waiting.begin());
  tbb::parallel_for_each(s.roots.begin(), s.roots.end(), [&](int32_t b, tbb::feeder<int32_t>& ready) {
    body(b);
    for (int32_t k = s.after_start[b]; k < s.after_start[b + 1]; ++k) {
      const int32_t c = s.after[k];
      // The last predecessor to finish hands c on; acq_rel orders every predecessor's writes
      // before c's reads.
      if (std::atomic_ref<int32_t>(s.waiting[c]).fetch_sub(1, std::memory_order_acq_rel) == 1) ready.add(c);
    }
  });
}

}  // namespace silt::dem
