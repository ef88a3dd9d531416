// What the DEM stages keep between steps that is not state: cell lists, the previous pair list
// during a rebuild, the renumbering, the pair schedule and the contact candidates. Rebuilt when
// invalid (after a restore or a replay: Simulation invalidates it), never hashed nor saved.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/workspace.hpp"
#include "dem/pair_schedule.hpp"
#include "silt/events.hpp"

namespace silt::dem {

struct DemWorkspace final : Workspace {
  std::vector<int32_t> cell_of, cell_start, cell_items, row_count;
  std::vector<std::vector<int32_t>> chunk_j;  // partners found per chunk of rows
  std::vector<int32_t> old_start, old_j;
  std::vector<double> old_hist;
  // The springs before the first state's force evaluation (dem::keep_springs), put back after it.
  std::vector<double> kept_pair_hist, kept_wall_hist;
  // Whether the forces of the state are made again (graph::Phase::kResolve: they were made under
  // other parameters, dem/forces_under.hpp), decided by the graph's first stage for the others.
  bool refresh = false;
  std::vector<int32_t> perm;           // new index -> old index of the last spatial sort
  std::vector<std::byte> permute_buf;  // a per-grain array being renumbered by perm
  PairSchedule schedule;               // of the current pair list when schedule_valid
  bool schedule_valid = false;
  // The threads' shares of the grains (core/owned.hpp), in the pair loop and the grain passes,
  // fitted to block_cost: the seconds each block took in the pair loop (kPairLoop) and in the
  // grain passes and the candidates' selection (kGrainPasses), halved at every rebalance.
  static constexpr size_t kPairLoop = 0, kGrainPasses = 1;
  Shares shares;
  LoopCosts block_cost = LoopCosts(2);
  // Contact candidates (dem/contact_candidates.hpp): the listed pairs of block b that may touch
  // are cand_p/i/j[nbr_start[b * kBlock] .. cand_end[b]) (pair index, grains).
  std::vector<int32_t> cand_p, cand_i, cand_j, cand_end;
  bool candidates_valid = false;
  double cand_travel = 0;  // bound on any grain's displacement since the selection [m]
  double cand_strain = 0;  // nbr_strain at the selection
  int64_t cand_selections = 0;

  // The step (State::step while it ran) that left its second half kick, of half step kick_h, to the
  // next step's kick_drift (dem::late_kick_drift). Only a step whose end nothing sees leaves it
  // (State::boundary_seen): a state that is saved, hashed, measured or restored never has a kick
  // due. The stages only compare it with State::step, so that running one twice (the access
  // check runs it on copies of the state) changes nothing.
  static constexpr int64_t kNoKickLeft = std::numeric_limits<int64_t>::min();
  int64_t kick_step = kNoKickLeft;
  double kick_h = 0;
  // The step whose pair loop also kicked the grains and ran the next step's kick_drift
  // (dem::kick_and_next_drift), the non-finite positions that drift met (for the next step to
  // raise) and each grain block's largest displacements.
  int64_t drift_step = kNoKickLeft;
  EventSlot drift_events;
  std::vector<std::array<double, 2>> block_disp;

  size_t bytes() const override {
    auto v = [](const auto& x) { return x.capacity() * sizeof(x[0]); };
    size_t b = v(cell_of) + v(cell_start) + v(cell_items) + v(row_count) + v(old_start) + v(old_j) + v(old_hist) +
               v(perm) + v(permute_buf) + v(block_cost[0]) + v(block_cost[1]) + v(cand_p) + v(cand_i) + v(cand_j) +
               v(cand_end) + v(block_disp);
    for (const auto& c : chunk_j) b += v(c);
    for (const auto* s : {&schedule.blocks, &schedule.colour_start, &schedule.n_before, &schedule.after_start,
                          &schedule.after, &schedule.roots, &schedule.clears_start, &schedule.clears, &schedule.waiting,
                          &schedule.finals_start, &schedule.finals, &schedule.grain_ready, &schedule.grain_done})
      b += v(*s);
    return b;
  }
  void invalidate() override {
    schedule_valid = false;
    candidates_valid = false;
    shares = {};
    kick_step = kNoKickLeft;
    drift_step = kNoKickLeft;
  }
  // The schedule of a new pair list, and the threads' shares rebalanced with it.
  void new_schedule(int64_t n, const std::vector<int32_t>& nbr_start, const std::vector<int32_t>& pair_j) {
    schedule = build_pair_schedule(n, nbr_start, pair_j);
    schedule_valid = true;
    rebalance(shares, block_cost, n);
  }
  void renumbered() override {}  // the renumbering rebuilds the list, its schedule and candidates
  // Contact candidates of the current selection.
  int64_t n_candidates(const std::vector<int32_t>& nbr_start) const {
    int64_t c = 0;
    for (size_t b = 0; b < cand_end.size(); ++b) c += cand_end[b] - nbr_start[b * PairSchedule::kBlock];
    return c;
  }
};

}  // namespace silt::dem
