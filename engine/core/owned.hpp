// Loops over grains that keep each grain on the same thread from one pass to the next.
//
// The grains are cut into blocks of kOwnedBlock (the pair loop's blocks, dem/pair_schedule.hpp)
// and the blocks into one contiguous share per thread of the arena: thread t (its arena slot)
// owns the blocks [begin[t], begin[t + 1]) of a Shares. An owned loop runs a thread's own blocks
// on it first, then lets it take the blocks another thread has not started (a thread that is late
// or busy elsewhere never holds the loop up). So in a step whose passes all go through these
// loops a grain's data is written and read by one core and stays in its caches: when a virtual
// machine's two cores are far apart (a cache line's round trip of 0.5 to 3 microseconds), a pass
// that reads what the other core just wrote can be several times as slow as on one core.
//
// Shares may be even or fitted to the measured cost of each block (a loop given a cost array adds
// each block's seconds to it). Which thread runs a block never changes what it computes: the loops
// write disjoint outputs, and their maxima are exact in any order.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <vector>

#include "core/parallel.hpp"

namespace silt {

inline constexpr int64_t kOwnedBlock = 1024;  // grains per block
inline constexpr int kMaxOwners = 64;         // an arena of more threads takes a plain split

// The blocks of n grains.
inline int64_t owned_blocks(int64_t n) { return (n + kOwnedBlock - 1) / kOwnedBlock; }

// The threads that own blocks: the arena's (0 when there are more than kMaxOwners).
inline int owner_count() {
  const int t = tbb::this_task_arena::max_concurrency();
  return t <= kMaxOwners ? std::max(t, 1) : 0;
}

// The calling thread's arena slot: the share it takes first.
inline int my_slot() { return std::clamp(tbb::this_task_arena::current_thread_index(), 0, kMaxOwners - 1); }

// A pause in a loop that waits on another thread.
inline void spin_pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Blocks [begin[t], begin[t + 1]) of `blocks` belong to owner t < owners.
struct Shares {
  int owners = 0;
  int64_t blocks = 0;
  std::array<int64_t, kMaxOwners + 1> begin{};
  int owner_of(int64_t b) const {
    return static_cast<int>(std::upper_bound(begin.begin() + 1, begin.begin() + owners, b) - (begin.begin() + 1));
  }
  // Whether these shares apply to nb blocks and `n` owners.
  bool fits(int64_t nb, int n) const { return owners == n && blocks == nb; }
};

// nb blocks in `owners` shares of as many blocks (within one).
inline Shares even_shares(int64_t nb, int owners) {
  Shares s;
  s.owners = owners;
  s.blocks = nb;
  for (int t = 0; t <= owners; ++t) s.begin[t] = nb * t / owners;
  return s;
}

// nb blocks in `owners` shares of about equal cost (cost[b] >= 0); even when nothing was measured.
inline Shares balanced_shares(const double* cost, int64_t nb, int owners) {
  double total = 0;
  for (int64_t b = 0; b < nb; ++b) total += cost[b];
  if (!(total > 0)) return even_shares(nb, owners);
  Shares s;
  s.owners = owners;
  s.blocks = nb;
  double sum = 0;
  int t = 1;
  for (int64_t b = 0; b < nb && t < owners; ++b) {
    // Block b goes to the share whose part of the total its middle falls in.
    const double mid = sum + 0.5 * cost[b];
    while (t < owners && mid >= total * t / owners) s.begin[t++] = b;
    sum += cost[b];
  }
  for (; t <= owners; ++t) s.begin[t] = nb;
  return s;
}

// The cost of the dearest share of `s` under the costs `cost`.
inline double largest_share(const Shares& s, const double* cost) {
  double top = 0;
  for (int t = 0; t < s.owners; ++t) {
    double c = 0;
    for (int64_t b = s.begin[t]; b < s.begin[t + 1]; ++b) c += cost[b];
    top = std::max(top, c);
  }
  return top;
}

// Costs of the blocks in loops that join one after the other: cost[l][b] seconds of block b in
// loop l (each loop waits for its dearest share).
using LoopCosts = std::vector<std::vector<double>>;

// The time of those loops under shares `s`: the sum of each loop's dearest share.
inline double joined_time(const Shares& s, const LoopCosts& cost) {
  double t = 0;
  for (const std::vector<double>& c : cost) t += largest_share(s, c.data());
  return t;
}

// Shares of nb blocks for loops that join one after the other: for two owners the boundary with
// the least joined time (every one tried, from each loop's prefix sums: a loop whose blocks cost
// unevenly, the pair loop, and one whose blocks cost the same, a grain pass, want different
// boundaries); for more, shares balanced by the summed cost. Even when nothing was measured.
inline Shares fitted_shares(const LoopCosts& cost, int64_t nb, int owners) {
  std::vector<double> sum(nb, 0.0);
  for (const std::vector<double>& c : cost)
    for (int64_t b = 0; b < nb; ++b) sum[b] += c[b];
  Shares best = balanced_shares(sum.data(), nb, owners);
  if (owners != 2) return best;
  // prefix[l * (nb + 1) + k]: loop l's cost of blocks [0, k).
  std::vector<double> prefix(cost.size() * (nb + 1), 0.0);
  for (size_t l = 0; l < cost.size(); ++l)
    for (int64_t b = 0; b < nb; ++b) prefix[l * (nb + 1) + b + 1] = prefix[l * (nb + 1) + b] + cost[l][b];
  auto joined_at = [&](int64_t k) {
    double t = 0;
    for (size_t l = 0; l < cost.size(); ++l) {
      const double* p = &prefix[l * (nb + 1)];
      t += std::max(p[k], p[nb] - p[k]);
    }
    return t;
  };
  double least = joined_at(best.begin[1]);
  for (int64_t k = 0; k <= nb; ++k)
    if (const double t = joined_at(k); t < least) {
      least = t;
      best.begin[1] = k;
    }
  return best;
}

// New shares of the blocks of n grains among the arena's threads, fitted to what each block cost
// in each loop since the last call, and taken when they shorten the joined time by more than a
// twentieth (a block that changes owner moves its grains' data to the other core once). The costs
// then halve: older ones count less.
inline void rebalance(Shares& shares, LoopCosts& cost, int64_t n) {
  const int64_t nb = owned_blocks(n);
  const int owners = static_cast<int>(std::min<int64_t>(owner_count(), nb));
  if (owners <= 1) {
    shares = {};
    return;
  }
  bool fits = shares.fits(nb, owners);
  for (const std::vector<double>& c : cost) fits = fits && static_cast<int64_t>(c.size()) == nb;
  if (!fits) {
    for (std::vector<double>& c : cost) c.assign(nb, 0.0);
    shares = even_shares(nb, owners);
    return;
  }
  const Shares next = fitted_shares(cost, nb, owners);
  if (joined_time(next, cost) < 0.95 * joined_time(shares, cost)) shares = next;
  for (std::vector<double>& c : cost)
    for (double& x : c) x *= 0.5;
}

// body(me) once on each of up to `owners` threads of the arena (at least on the caller), me the
// thread's slot.
template <class F>
void on_owners(int owners, F&& body) {
  tbb::parallel_for(
      tbb::blocked_range<int>(0, owners, 1), [&](const tbb::blocked_range<int>&) { body(my_slot()); },
      tbb::simple_partitioner{});
}

// Which shares a thread has taken, in one loop: each is taken whole by one thread.
class ShareClaims {
 public:
  explicit ShareClaims(int owners) : owners_(owners) {
    for (int t = 0; t < owners; ++t) flag_[t].taken.store(0, std::memory_order_relaxed);
  }
  bool take(int t) { return flag_[t].taken.exchange(1, std::memory_order_relaxed) == 0; }
  bool all_taken() const {
    for (int t = 0; t < owners_; ++t)
      if (!flag_[t].taken.load(std::memory_order_relaxed)) return false;
    return true;
  }

 private:
  struct alignas(64) Flag {
    std::atomic<int> taken;
  };
  int owners_;
  std::array<Flag, kMaxOwners> flag_;
};

// f(), its seconds added to *seconds when seconds is not null.
template <class F>
void timed(double* seconds, F&& f) {
  if (!seconds) return f();
  const auto t0 = std::chrono::steady_clock::now();
  f();
  *seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// f(begin, end) for each block of kOwnedBlock grains of [0, n) (one call per block). Each thread
// takes its own share under `shares` (even shares when they do not fit), then the shares no
// thread has taken yet, each whole: a thread never takes blocks from a share another thread is
// running, whose grains are in that thread's caches. With shares that fit and `cost` (nb
// entries), each block's seconds are added to cost[b].
template <class F>
void owned_for(int64_t n, const Shares& shares, double* cost, F&& f) {
  const int64_t nb = owned_blocks(n);
  auto block = [&](int64_t b) { f(b * kOwnedBlock, std::min(n, (b + 1) * kOwnedBlock)); };
  const int all = owner_count();
  if (all == 0) {
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, nb, 1), [&](const tbb::blocked_range<int64_t>& r) {
      for (int64_t b = r.begin(); b < r.end(); ++b) block(b);
    });
    return;
  }
  const int owners = static_cast<int>(std::min<int64_t>(all, nb));
  if (owners <= 1) {
    for (int64_t b = 0; b < nb; ++b) block(b);
    return;
  }
  const bool fit = shares.fits(nb, owners);
  Shares even;
  if (!fit) even = even_shares(nb, owners);
  const Shares& s = fit ? shares : even;
  ShareClaims taken(owners);
  on_owners(owners, [&](int me) {
    for (int k = 0; k < owners; ++k) {
      const int t = (me + k) % owners;  // its own share first
      if (!taken.take(t)) continue;
      for (int64_t b = s.begin[t]; b < s.begin[t + 1]; ++b) timed(fit && cost ? cost + b : nullptr, [&] { block(b); });
    }
  });
}

// K maxima over [0, n) of f(begin, end) (std::array<double, K> per block; 0 for none), the blocks
// run (and timed) as owned_for runs them, each thread keeping its own maxima (a thread runs its blocks one
// after the other). A NaN of any block stays.
template <size_t K, class F>
std::array<double, K> owned_max(int64_t n, const Shares& shares, double* cost, F&& f) {
  using A = std::array<double, K>;
  if (owner_count() == 0) return parallel_max<K>(n, kOwnedBlock, f);  // slots beyond kMaxOwners
  struct alignas(64) Slot {
    A m{};
  };
  std::array<Slot, kMaxOwners> part{};
  owned_for(n, shares, cost, [&](int64_t b, int64_t e) { max_into(part[my_slot()].m, f(b, e)); });
  A m{};
  for (const Slot& p : part) max_into(m, p.m);
  return m;
}

}  // namespace silt
