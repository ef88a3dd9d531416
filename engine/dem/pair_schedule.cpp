#include "dem/pair_schedule.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#include "core/parallel.hpp"

namespace silt::dem {

namespace {

// items grouped by key(item) in [0, n_keys), each group in the items' order: group k is
// out[start[k] .. start[k + 1]) (a counting sort).
template <class Key>
void group_by(const std::vector<int32_t>& items, int64_t n_keys, Key&& key, std::vector<int32_t>& start,
              std::vector<int32_t>& out) {
  start.assign(n_keys + 1, 0);
  for (int32_t x : items) ++start[key(x) + 1];
  for (int64_t k = 0; k < n_keys; ++k) start[k + 1] += start[k];
  out.resize(items.size());
  std::vector<int32_t> pos(start.begin(), start.end() - 1);
  for (int32_t x : items) out[pos[key(x)]++] = x;
}

std::vector<int32_t> iota(int64_t n) {
  std::vector<int32_t> v(n);
  for (int64_t k = 0; k < n; ++k) v[k] = static_cast<int32_t>(k);
  return v;
}

// The graph of the schedule: the blocks that write grain block t, taken in colour order, form a
// chain (they conflict pairwise, so their colours differ); the union of these chains orders every
// two blocks that write a common grain as their colours do, and no others.
void link_blocks(PairSchedule& s, const std::vector<std::vector<int32_t>>& targets) {
  const int64_t nb = static_cast<int64_t>(targets.size());
  std::vector<int32_t> last(nb, -1);  // the latest writer of each grain block so far
  std::vector<std::vector<int32_t>> after(nb), clears(nb);
  for (int32_t b : s.blocks)  // colour order
    for (int32_t t : targets[b]) {
      if (last[t] < 0) clears[b].push_back(t);
      else after[last[t]].push_back(b);
      last[t] = b;
    }
  s.n_before.assign(nb, 0);
  s.after_start.assign(nb + 1, 0);
  s.clears_start.assign(nb + 1, 0);
  s.after.clear();
  s.clears.clear();
  for (int64_t b = 0; b < nb; ++b) {
    std::vector<int32_t>& a = after[b];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    for (int32_t c : a) ++s.n_before[c];
    s.after.insert(s.after.end(), a.begin(), a.end());
    s.after_start[b + 1] = static_cast<int32_t>(s.after.size());
    s.clears.insert(s.clears.end(), clears[b].begin(), clears[b].end());
    s.clears_start[b + 1] = static_cast<int32_t>(s.clears.size());
  }
  s.roots.clear();
  for (int32_t b : s.blocks)
    if (s.n_before[b] == 0) s.roots.push_back(b);
  s.waiting.assign(nb, 0);
  // The grain blocks by their last writer (every block writes its own).
  group_by(
      iota(nb), nb, [&](int32_t t) { return last[t]; }, s.finals_start, s.finals);
  s.grain_ready.assign(nb, 0);
  s.grain_done.assign(nb, 0);
}

}  // namespace

PairSchedule build_pair_schedule(int64_t n, const std::vector<int32_t>& nbr_start, const std::vector<int32_t>& pair_j) {
  constexpr int64_t B = PairSchedule::kBlock;
  const int64_t nb = (n + B - 1) / B;
  // targets[b]: the blocks that block b writes (its own and those of its partners), sorted.
  std::vector<std::vector<int32_t>> targets(nb);
  parallel_for(nb, 8, [&](int64_t b0, int64_t b1) {
    for (int64_t b = b0; b < b1; ++b) {
      std::vector<int32_t>& t = targets[b];
      t.push_back(static_cast<int32_t>(b));
      const int64_t end = std::min(n, (b + 1) * B);
      for (int32_t p = nbr_start[b * B]; p < nbr_start[end]; ++p) t.push_back(static_cast<int32_t>(pair_j[p] / B));
      std::sort(t.begin(), t.end());
      t.erase(std::unique(t.begin(), t.end()), t.end());
    }
  });
  // used[t]: the colours of the blocks already coloured that write block t (a bitset; there are
  // at most nb colours).
  const int64_t words = (nb + 63) / 64;
  std::vector<uint64_t> used(nb * words, 0), taken(words);
  std::vector<int32_t> colour(nb, 0);
  int n_colours = 0;
  for (int64_t b = 0; b < nb; ++b) {
    std::fill(taken.begin(), taken.end(), 0);
    for (int32_t t : targets[b])
      for (int64_t k = 0; k < words; ++k) taken[k] |= used[t * words + k];
    int64_t k = 0;
    while (taken[k] == ~uint64_t{0}) ++k;
    const int c = static_cast<int>(64 * k + std::countr_one(taken[k]));
    colour[b] = c;
    n_colours = std::max(n_colours, c + 1);
    for (int32_t t : targets[b]) used[t * words + c / 64] |= uint64_t{1} << (c % 64);
  }
  PairSchedule s;
  group_by(
      iota(nb), n_colours, [&](int32_t b) { return colour[b]; }, s.colour_start, s.blocks);
  link_blocks(s, targets);
  return s;
}

void split_by_owner(PairSchedule& s, const Shares& shares) {
  group_by(
      s.blocks, shares.owners, [&](int32_t b) { return shares.owner_of(b); }, s.own_start, s.own);
  // Nearness: the fewest edges of the schedule's graph (conflicts, either way) from a block with
  // an edge to another owner's block; a stable sort keeps the schedule's order among blocks as near.
  const int64_t nb = static_cast<int64_t>(s.n_before.size());
  std::vector<std::vector<int32_t>> near(nb);
  for (int64_t b = 0; b < nb; ++b)
    for (int32_t k = s.after_start[b]; k < s.after_start[b + 1]; ++k) {
      near[b].push_back(s.after[k]);
      near[s.after[k]].push_back(static_cast<int32_t>(b));
    }
  std::vector<int32_t> hops(nb, std::numeric_limits<int32_t>::max()), front;
  for (int64_t b = 0; b < nb; ++b)
    for (int32_t c : near[b])
      if (shares.owner_of(c) != shares.owner_of(b) && hops[b] != 0) {
        hops[b] = 0;
        front.push_back(static_cast<int32_t>(b));
      }
  for (size_t q = 0; q < front.size(); ++q)  // breadth first
    for (int32_t c : near[front[q]])
      if (hops[c] == std::numeric_limits<int32_t>::max()) {
        hops[c] = hops[front[q]] + 1;
        front.push_back(c);
      }
  for (int t = 0; t < shares.owners; ++t)
    std::stable_sort(s.own.begin() + s.own_start[t], s.own.begin() + s.own_start[t + 1],
                     [&](int32_t a, int32_t b) { return hops[a] < hops[b]; });
  s.claimed.assign(s.blocks.size(), 0);
  s.split = shares;
}

}  // namespace silt::dem
