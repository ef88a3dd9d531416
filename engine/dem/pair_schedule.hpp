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
#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/owned.hpp"
#include "silt/state.hpp"

namespace silt::dem {

// A conflict-free order of the pair loop's blocks of rows.
struct PairSchedule {
  static constexpr int64_t kBlock = kOwnedBlock;  // rows per block
  std::vector<int32_t> blocks;                    // block indices, grouped by colour
  std::vector<int32_t> colour_start;              // colour c holds blocks[colour_start[c] .. colour_start[c + 1])
  int colours() const { return static_cast<int>(colour_start.size()) - 1; }
  // The same order as a graph: block b may run once its n_before[b] predecessors have run (the
  // blocks of earlier colours that write a grain it writes, the nearest for each such grain); its
  // successors are after[after_start[b] .. after_start[b + 1]). roots: the blocks without
  // predecessors. Block b is the first to write the grains of the blocks
  // clears[clears_start[b] .. clears_start[b + 1]).
  std::vector<int32_t> n_before, after_start, after, roots, clears_start, clears;
  // Block b is the last to write the grains of the blocks finals[finals_start[b] ..
  // finals_start[b + 1]): once it has run, their sums are complete and no block reads them.
  std::vector<int32_t> finals_start, finals;
  std::vector<int32_t> grain_ready, grain_done;  // per grain block, during a pass with a grain pass
  std::vector<int32_t> waiting;                  // predecessors not yet run, during a pass
  // The blocks of each owner in the schedule's order (split_by_owner) and, during a pass, which
  // blocks a thread has taken.
  Shares split;
  std::vector<int32_t> own, own_start, claimed;
};

// No pass over the grain blocks in run_pair_schedule.
struct NoGrainPass {
  void operator()(int32_t) const {}
};

// Scans of a thread's blocks, none ready, before it takes the shares no thread has taken.
inline constexpr int kPatience = 1024;

// The schedule of a half list in CSR form (row i holds its partners j).
PairSchedule build_pair_schedule(int64_t n, const std::vector<int32_t>& nbr_start, const std::vector<int32_t>& pair_j);

// The blocks of each owner of `shares` (core/owned.hpp): owner t's are own[own_start[t] ..
// own_start[t + 1]), those nearest another owner's blocks first (fewest conflicts away from a
// block that conflicts with one), each as near in the schedule's order. The other threads wait on
// those, so they run first: on two threads in a fast flow, shares taken in colour order left the
// second thread waiting on the first one's blocks for up to a fifth of the loop.
void split_by_owner(PairSchedule& s, const Shares& shares);

// body(b) for every block b of the schedule, each after the blocks before it in the schedule's
// order that write the same grains, and in parallel with the others. Each thread takes the blocks
// of its own share of the grains (`shares`, even ones when they do not fit) and runs them in the
// order of split_by_owner as they become ready, so the grains a block writes stay with the thread that
// moves them in the grain passes (core/owned.hpp). A share whose thread has not come after
// kPatience scans of a waiting thread is taken whole by that thread. With shares that fit and
// `cost` (a value per block), each block's seconds are added to cost[b].
//
// With a grain pass, grain(g) runs once for every grain block g, as soon as the last block that
// writes its grains has run (PairSchedule::finals), by the thread that holds g's share, which
// runs its ready grain blocks before its next pair block; its seconds are added to cost[g] too.
template <class F, class G = NoGrainPass>
void run_pair_schedule(PairSchedule& s, const Shares& shares, double* cost, F&& body, G&& grain = {}) {
  constexpr bool kGrains = !std::is_same_v<std::decay_t<G>, NoGrainPass>;
  const int64_t nb = static_cast<int64_t>(s.blocks.size());
  const int all = owner_count();
  const int owners = static_cast<int>(std::min<int64_t>(all, nb));
  auto finals = [&](int32_t b) {
    if constexpr (kGrains)
      for (int32_t k = s.finals_start[b]; k < s.finals_start[b + 1]; ++k) grain(s.finals[k]);
  };
  if (all == 1 || nb <= 1) {
    for (int32_t b : s.blocks) {
      body(b);
      finals(b);
    }
    return;
  }
  std::copy(s.n_before.begin(), s.n_before.end(), s.waiting.begin());
  if (all == 0) {  // more threads than owners: blocks to whichever thread is free
    tbb::parallel_for_each(s.roots.begin(), s.roots.end(), [&](int32_t b, tbb::feeder<int32_t>& ready) {
      body(b);
      finals(b);
      for (int32_t k = s.after_start[b]; k < s.after_start[b + 1]; ++k)
        if (std::atomic_ref<int32_t>(s.waiting[s.after[k]]).fetch_sub(1, std::memory_order_acq_rel) == 1)
          ready.add(s.after[k]);
    });
    return;
  }
  const bool fit = shares.fits(nb, owners);
  Shares even;
  if (!fit) even = even_shares(nb, owners);
  const Shares& split = fit ? shares : even;
  if (s.split.owners != owners || s.split.begin != split.begin) split_by_owner(s, split);
  std::fill(s.claimed.begin(), s.claimed.end(), 0);  // the blocks run in this pass
  if constexpr (kGrains) {
    std::fill(s.grain_ready.begin(), s.grain_ready.end(), 0);
    std::fill(s.grain_done.begin(), s.grain_done.end(), 0);
  }
  ShareClaims taken(owners);
  on_owners(owners, [&](int me) {
    // The shares this thread took, and in each the position of its first block (and first grain
    // block) not yet run.
    std::array<int32_t, kMaxOwners> mine, from, grain_from;
    int n_mine = 0;
    if (me < owners && taken.take(me)) mine[n_mine++] = me;  // more threads than blocks: me may own none
    for (int t = 0; t < owners; ++t) {
      from[t] = s.own_start[t];
      grain_from[t] = static_cast<int32_t>(split.begin[t]);
    }
    int idle = 0;
    for (;;) {
      bool ran = false, left = false;
      for (int q = 0; q < n_mine && !ran; ++q) {
        const int t = mine[q];
        if constexpr (kGrains) {
          // Its grain blocks whose sums are complete, first: their grains are in this core's cache.
          const auto end = static_cast<int32_t>(split.begin[t + 1]);
          for (int32_t g = grain_from[t]; g < end; ++g) {
            if (s.grain_done[g]) continue;
            left = true;
            if (std::atomic_ref<int32_t>(s.grain_ready[g]).load(std::memory_order_acquire) == 0) continue;
            s.grain_done[g] = 1;
            timed(fit && cost ? cost + g : nullptr, [&] { grain(g); });
            ran = true;
            break;
          }
          while (grain_from[t] < end && s.grain_done[grain_from[t]]) ++grain_from[t];
          if (ran) break;
        }
        for (int32_t k = from[t]; k < s.own_start[t + 1]; ++k) {
          const int32_t b = s.own[k];
          if (s.claimed[b]) continue;
          left = true;
          // The last predecessor to finish made b ready; acq_rel orders every predecessor's
          // writes before b's reads.
          if (std::atomic_ref<int32_t>(s.waiting[b]).load(std::memory_order_acquire) != 0) continue;
          s.claimed[b] = 1;
          timed(fit && cost ? cost + b : nullptr, [&] { body(b); });
          for (int32_t a = s.after_start[b]; a < s.after_start[b + 1]; ++a)
            std::atomic_ref<int32_t>(s.waiting[s.after[a]]).fetch_sub(1, std::memory_order_acq_rel);
          if constexpr (kGrains)  // b's writes, and by the chain of writers all earlier ones, before g's pass
            for (int32_t f = s.finals_start[b]; f < s.finals_start[b + 1]; ++f)
              std::atomic_ref<int32_t>(s.grain_ready[s.finals[f]]).store(1, std::memory_order_release);
          ran = true;
          break;
        }
        while (from[t] < s.own_start[t + 1] && s.claimed[s.own[from[t]]]) ++from[t];
      }
      if (ran) {
        idle = 0;
        continue;
      }
      if (!left && taken.all_taken()) return;  // its shares are done, the others have threads
      if (++idle < kPatience) {
        spin_pause();
        continue;
      }
      idle = 0;
      for (int t = 0; t < owners; ++t)
        if (taken.take(t)) mine[n_mine++] = t;
    }
  });
}

}  // namespace silt::dem
