// The touch pass of contact_forces: the four-lane (AVX2), two-lane and scalar paths give the
// same pairs and the same separations (with their norms and inverses), bit for bit, as the
// nearest-image arithmetic of PeriodicImage, in periodic and Lees-Edwards boxes, in 2D and 3D;
// forces and springs of pairs just come apart are cleared, the others left alone. Entry q of the
// pass is pair pp[q] (here the pairs in reverse), whose flags, forces and springs it updates.
#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "core/simd_level.hpp"
#include "dem/touch_pass.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

template <int D>
void check_touch_pass(bool lees_edwards, int64_t n_pairs) {
  Box box;
  for (int k = 0; k < D; ++k) {
    box.lo[k] = -1.0 + 0.5 * k;
    box.len[k] = 6.0 + k;
    box.periodic[k] = k < 2 || !lees_edwards;
  }
  box.lees_edwards = lees_edwards;
  box.le_offset = lees_edwards ? 2.37 : 0.0;
  const PeriodicImage<D> img(box);
  std::mt19937_64 rng(17 + D + 10 * lees_edwards);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 40;
  std::vector<double> x(D * n), r(n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < D; ++k) x[D * i + k] = box.lo[k] + box.len[k] * u(rng);
    r[i] = 0.6 + 0.9 * u(rng);  // many pairs touch, many do not
  }
  std::vector<int32_t> pi(n_pairs), pj(n_pairs);
  std::vector<uint8_t> touch(n_pairs);
  std::vector<double> pf(D * n_pairs), hist(D * n_pairs);
  for (int64_t p = 0; p < n_pairs; ++p) {
    pi[p] = static_cast<int32_t>(rng() % n);
    pj[p] = static_cast<int32_t>((pi[p] + 1 + rng() % (n - 1)) % n);
    touch[p] = rng() % 2;
    for (int k = 0; k < D; ++k) pf[D * p + k] = hist[D * p + k] = 1.0 + p;
  }
  std::vector<int32_t> pp(n_pairs);
  for (int64_t q = 0; q < n_pairs; ++q) pp[q] = static_cast<int32_t>(n_pairs - 1 - q);
  const std::vector<uint8_t> before = touch;
  std::vector<int32_t> tp(n_pairs);
  std::vector<double> td((D + 2) * n_pairs);
  double* td_cols[D + 2];
  for (int k = 0; k < D + 2; ++k) td_cols[k] = td.data() + k * n_pairs;
  const int64_t c =
      dem::touch_pass<D>({x.data(), r.data(), pp.data(), pi.data(), pj.data(), touch.data(), pf.data(), hist.data()},
                         img, 0, n_pairs, tp.data(), td_cols);
  int64_t expect = 0, apart = 0;
  for (int64_t q = 0; q < n_pairs; ++q) {
    const int64_t p = pp[q];
    SVec<D> d = SVec<D>::load(&x[D * pi[q]]) - SVec<D>::load(&x[D * pj[q]]);
    img.apply(d);
    const double rs = r[pi[q]] + r[pj[q]];
    const bool now = d.squaredNorm() < rs * rs;
    CHECK(touch[p] == now);
    const double kept = (before[p] && !now) ? 0.0 : 1.0 + p;
    for (int k = 0; k < D; ++k) {
      CHECK(pf[D * p + k] == kept);
      CHECK(hist[D * p + k] == kept);
    }
    apart += !now;
    if (!now) continue;
    REQUIRE(expect < c);
    CHECK(tp[expect] == p);
    for (int k = 0; k < D; ++k) CHECK(td_cols[k][expect] == d[k]);
    CHECK(td_cols[D][expect] == d.norm());
    CHECK(td_cols[D + 1][expect] == 1.0 / d.norm());
    ++expect;
  }
  CHECK(c == expect);
  if (n_pairs >= 100) {  // both kinds present, so both branches ran
    CHECK(c > 0);
    CHECK(apart > 0);
  }
}

}  // namespace

TEST_CASE("touch pass matches the nearest-image test bit for bit (periodic and Lees-Edwards, 2D and 3D)") {
  for (SimdLevel level : {SimdLevel::kAvx512, SimdLevel::kAvx2, SimdLevel::kBaseline}) {
    limit_simd(level);  // the widest the processor has, then narrower
    for (int64_t n_pairs : {1, 2, 5, 7, 200, 201, 203}) {
      check_touch_pass<2>(false, n_pairs);
      check_touch_pass<3>(false, n_pairs);
      check_touch_pass<2>(true, n_pairs);
      check_touch_pass<3>(true, n_pairs);
    }
  }
  limit_simd(SimdLevel::kAvx512);
}

TEST_CASE("after every step pair_touch says which listed pairs touch, and pairs apart hold no force or spring") {
  // The chute starts as a lattice with gaps of 0.02 diameters and collapses: pairs come into
  // contact and part again, across neighbour-list rebuilds, while the force pass only clears
  // the pairs it saw touching the step before.
  Simulation sim(compile(load_scene_file(test::scene_path("chute"))), 2);
  int64_t touching_seen = 0;
  for (int step = 0; step < 400; ++step) {
    REQUIRE(sim.step());
    const State& s = sim.state();
    const PeriodicImage<3> img(s.box);
    int64_t wrong = 0;
    for (int64_t p = 0; p < s.n_pairs(); ++p) {
      const int32_t i = s.pair_i[p], j = s.pair_j[p];
      SVec<3> d = SVec<3>::load(&s.particle_x[3 * i]) - SVec<3>::load(&s.particle_x[3 * j]);
      img.apply(d);
      const double rs = s.particle_r[i] + s.particle_r[j];
      const bool now = d.squaredNorm() < rs * rs;
      touching_seen += now;
      wrong += s.pair_touch[p] != now;
      if (!now)
        for (int k = 0; k < 3; ++k) wrong += s.pair_f[3 * p + k] != 0 || s.pair_hist[3 * p + k] != 0;
    }
    REQUIRE(wrong == 0);
  }
  CHECK(touching_seen > 0);
  CHECK(sim.state().nbr_builds > 1);
}
