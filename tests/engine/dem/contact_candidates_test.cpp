// Contact candidates: after every step every touching pair is a candidate, candidates keep the
// list's order, and the run is the same, bit for bit, whatever the contact skin (0: every listed
// pair; a tiny one: re-selected nearly every step), in sheared 2D and 3D boxes with friction.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/small_vec.hpp"
#include "dem/contact_candidates.hpp"
#include "dem/workspace.hpp"
#include "silt/periodic_image.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"
#include "support/scenes.hpp"

using namespace silt;
using silt::dem::PairSchedule;

namespace {

std::string scene(int dim, double contact_skin) { return test::frictional_gas(dim, 3.0, 0.0, contact_skin); }

// Every pair touching now is among the candidates of its block, which are in list order.
template <int D>
int64_t missing_candidates(const State& s, const dem::DemWorkspace& sc) {
  const PeriodicImage<D> img(s.box);
  std::vector<char> is_cand(s.n_pairs(), 0);
  int64_t bad = 0;
  for (size_t b = 0; b < sc.cand_end.size(); ++b) {
    const int64_t q0 = s.nbr_start[b * PairSchedule::kBlock];
    for (int64_t q = q0; q < sc.cand_end[b]; ++q) {
      is_cand[sc.cand_p[q]] = 1;
      bad += sc.cand_i[q] != s.pair_i[sc.cand_p[q]] || sc.cand_j[q] != s.pair_j[sc.cand_p[q]];
      bad += q > q0 && sc.cand_p[q] <= sc.cand_p[q - 1];
    }
  }
  for (int64_t p = 0; p < s.n_pairs(); ++p) {
    const int32_t i = s.pair_i[p], j = s.pair_j[p];
    SVec<D> d = SVec<D>::load(&s.particle_x[D * i]) - SVec<D>::load(&s.particle_x[D * j]);
    img.apply(d);
    const double rs = s.particle_r[i] + s.particle_r[j];
    bad += d.squaredNorm() < rs * rs && !is_cand[p];
  }
  return bad;
}

}  // namespace

TEST_CASE("contact candidates hold every touching pair and change no bit of the run") {
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    std::vector<uint64_t> hashes;
    for (double cs : {0.0, 0.06, 0.003}) {
      CAPTURE(cs);
      auto sim = test::simulation_from(scene(dim, cs), 2);
      int64_t touching = 0, candidates = 0, pairs = 0;
      for (int step = 0; step < 300; ++step) {
        REQUIRE(sim->step());
        const State& s = sim->state();
        const dem::DemWorkspace& w = test::dem_workspace(*sim);
        REQUIRE((dim == 2 ? missing_candidates<2>(s, w) : missing_candidates<3>(s, w)) == 0);
        candidates += w.n_candidates(s.nbr_start);
        pairs += s.n_pairs();
        for (uint8_t t : s.pair_touch) touching += t;
      }
      const State& s = sim->state();
      CHECK(touching > 0);
      if (cs == 0) {
        CHECK(candidates == pairs);  // every listed pair
      } else {
        CHECK(candidates < pairs);
        CHECK(test::dem_workspace(*sim).cand_selections > s.nbr_builds);  // re-selected between rebuilds
      }
      hashes.push_back(state_hash(s));
    }
    CHECK(hashes[1] == hashes[0]);
    CHECK(hashes[2] == hashes[0]);
  }
}
