#include "dem/contact_candidates.hpp"

#include <algorithm>
#include <cstdint>

#include "core/buffers.hpp"
#include "core/owned.hpp"
#include "dem/pair_schedule.hpp"
#include "dem/touch_pass.hpp"

namespace silt::dem {
namespace {

template <int D, bool All>
void select_block(State& s, DemWorkspace& sc, const PeriodicImage<D>& img, double gap, int64_t blk) {
  constexpr int64_t B = PairSchedule::kBlock;
  const int64_t p0 = s.nbr_start[blk * B], p1 = s.nbr_start[std::min(s.n, (blk + 1) * B)];
  const int32_t* pi = s.pair_i.data();
  const int32_t* pj = s.pair_j.data();
  int32_t* cp = sc.cand_p.data() + p0;
  int32_t* ci = sc.cand_i.data() + p0;
  int32_t* cj = sc.cand_j.data() + p0;
  // Stored whether kept or not, then counted: which pairs are kept follows no pattern.
  const auto keep = [=](int64_t p, uint8_t kept, int64_t c) {
    cp[c] = static_cast<int32_t>(p);
    ci[c] = pi[p];
    cj[c] = pj[p];
    return c + kept;
  };
  int64_t c = 0;
  if constexpr (All) {
    for (int64_t p = p0; p < p1; ++p) c = keep(p, 1, c);
  } else {
    // Entry p is pair p here.
    const TouchArrays ta{s.particle_x.data(), s.particle_r.data(), nullptr,           pi, pj,
                         s.pair_touch.data(), s.pair_f.data(),     s.pair_hist.data()};
    c = scan_pairs<D, true>(s.particle_x.data(), s.particle_r.data(), pi, pj, img, gap, p0, p1,
                            [=](int64_t p, const double*, uint8_t within, int64_t n) {
                              // A pair left out is apart: clear what it may hold, as the touch
                              // pass would (rare, so the branch is well predicted).
                              if (!within) update_touch<D>(ta, p, 0);
                              return keep(p, within, n);
                            });
  }
  sc.cand_end[blk] = static_cast<int32_t>(p0 + c);
}

template <int D>
void select_dim(const Model& m, State& s, DemWorkspace& sc) {
  const int64_t np = s.n_pairs();
  const int64_t nb = (s.n + PairSchedule::kBlock - 1) / PairSchedule::kBlock;
  resize_tight(sc.cand_p, np);
  resize_tight(sc.cand_i, np);
  resize_tight(sc.cand_j, np);
  sc.cand_end.assign(nb, 0);
  const PeriodicImage<D> img(s.box);
  const bool all = m.contact_skin >= m.skin;
  // Each block on the thread that owns its rows (core/owned.hpp), as in the pair loop.
  owned_for(s.n, sc.shares, sc.block_cost[DemWorkspace::kGrainPasses].data(), [&](int64_t b, int64_t) {
    const int64_t k = b / kOwnedBlock;
    if (all) select_block<D, true>(s, sc, img, m.contact_skin, k);
    else select_block<D, false>(s, sc, img, m.contact_skin, k);
  });
  sc.candidates_valid = true;
  ++sc.cand_selections;
  sc.cand_travel = 0;
  sc.cand_strain = s.nbr_strain;
}

void choose(const Model& m, State& s, DemWorkspace& w) {
  if (m.dim == 2) select_dim<2>(m, s, w);
  else select_dim<3>(m, s, w);
}

}  // namespace

void select_candidates(const Model& m, State& s, DemWorkspace& w) { choose(m, s, w); }

void update_candidates(const Model& m, State& s, DemWorkspace& sc, bool rebuilt) {
  if (!rebuilt && sc.candidates_valid) {
    if (m.contact_skin >= m.skin) return;  // every listed pair: valid as long as the list
    sc.cand_travel += s.nbr_step_disp;
    if (2 * sc.cand_travel + (s.nbr_strain - sc.cand_strain) * m.interaction_range() <= m.contact_skin) return;
  }
  choose(m, s, sc);
}

}  // namespace silt::dem
