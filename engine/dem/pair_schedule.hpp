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
// With grains in cell order (see neighbor_list.cpp) a block's partners lie within about one
// layer of cells, and a few colours suffice; without that order the schedule stays correct and
// only runs more serially.
#pragma once

#include <cstdint>
#include <vector>

#include "silt/state.hpp"

namespace silt::dem {

// The schedule of a half list in CSR form (row i holds its partners j).
PairSchedule build_pair_schedule(int64_t n, const std::vector<int32_t>& nbr_start, const std::vector<int32_t>& pair_j);

}  // namespace silt::dem
