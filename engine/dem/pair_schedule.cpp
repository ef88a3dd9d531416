#include "dem/pair_schedule.hpp"

#include <algorithm>
#include <bit>

namespace silt::dem {

namespace {

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
  // The last writer of each grain block (every block writes its own).
  s.finals_start.assign(nb + 1, 0);
  for (int64_t t = 0; t < nb; ++t) ++s.finals_start[last[t] + 1];
  for (int64_t b = 0; b < nb; ++b) s.finals_start[b + 1] += s.finals_start[b];
  s.finals.resize(nb);
  std::vector<int32_t> pos(s.finals_start.begin(), s.finals_start.end() - 1);
  for (int64_t t = 0; t < nb; ++t) s.finals[pos[last[t]]++] = static_cast<int32_t>(t);
  s.grain_ready.assign(nb, 0);
  s.grain_done.assign(nb, 0);
}

}  // namespace

PairSchedule build_pair_schedule(int64_t n, const std::vector<int32_t>& nbr_start, const std::vector<int32_t>& pair_j) {
  constexpr int64_t B = PairSchedule::kBlock;
  const int64_t nb = (n + B - 1) / B;
  // targets[b]: the blocks that block b writes (its own and those of its partners), sorted.
  std::vector<std::vector<int32_t>> targets(nb);
  for (int64_t b = 0; b < nb; ++b) {
    std::vector<int32_t>& t = targets[b];
    t.push_back(static_cast<int32_t>(b));
    const int64_t end = std::min(n, (b + 1) * B);
    for (int32_t p = nbr_start[b * B]; p < nbr_start[end]; ++p) t.push_back(static_cast<int32_t>(pair_j[p] / B));
    std::sort(t.begin(), t.end());
    t.erase(std::unique(t.begin(), t.end()), t.end());
  }
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
  s.colour_start.assign(n_colours + 1, 0);
  for (int64_t b = 0; b < nb; ++b) ++s.colour_start[colour[b] + 1];
  for (int c = 0; c < n_colours; ++c) s.colour_start[c + 1] += s.colour_start[c];
  s.blocks.resize(nb);
  std::vector<int32_t> pos(s.colour_start.begin(), s.colour_start.end() - 1);
  for (int64_t b = 0; b < nb; ++b) s.blocks[pos[colour[b]]++] = static_cast<int32_t>(b);
  link_blocks(s, targets);
  return s;
}

void split_by_owner(PairSchedule& s, const Shares& shares) {
  const int owners = shares.owners;
  s.own_start.assign(owners + 1, 0);
  for (int32_t b : s.blocks) ++s.own_start[shares.owner_of(b) + 1];
  for (int t = 0; t < owners; ++t) s.own_start[t + 1] += s.own_start[t];
  s.own.resize(s.blocks.size());
  std::vector<int32_t> pos(s.own_start.begin(), s.own_start.end() - 1);
  for (int32_t b : s.blocks) s.own[pos[shares.owner_of(b)]++] = b;
  s.claimed.assign(s.blocks.size(), 0);
  s.split = shares;
}

}  // namespace silt::dem
