#include "dem/pair_schedule.hpp"

#include <algorithm>
#include <bit>

namespace silt::dem {

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
  return s;
}

}  // namespace silt::dem
