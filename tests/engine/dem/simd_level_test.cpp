// The AVX2 kernels and the baseline ones give the same bits: frictional contacts in 2D and 3D,
// with and without a tangential dashpot, many of them sliding, in fixed and sheared
// (Lees-Edwards) boxes.
#include <doctest/doctest.h>

#include "dem/simd_level.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

const char* kGas = R"(
[scene]
dimension = {dim}
seed = 3
[domain]
lo = LO
hi = HI
periodic = PER
[contact]
model = "hooke"
k_n = 5e4
gamma_n = 15
friction = 0.3
tangential_damping = {zt}
[[grains]]
count = {n}
radius_min = 0.35
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 3.0
[run]
dt = 2e-4
)";

uint64_t hash_after(int dim, double zeta_t, bool sheared, bool baseline) {
  dem::limit_to_baseline(baseline);
  const bool d3 = dim == 3;
  const std::string text =
      test::fill(test::with_lists(kGas, d3 ? "[0, 0, 0]" : "[0, 0]", d3 ? "[6, 6, 6]" : "[14, 14]",
                                  d3 ? "[true, true, true]" : "[true, true]"),
                 {{"dim", dim}, {"n", d3 ? 200 : 150}, {"zt", zeta_t}}) +
      (sheared ? "[shear]\nrate = 2.0\n" : "");
  auto sim = test::simulation_from(text);
  for (int k = 0; k < 300; ++k) REQUIRE(sim->step());
  dem::limit_to_baseline(false);
  return state_hash(sim->state());
}

}  // namespace

TEST_CASE("AVX2 and baseline kernels give the same bits") {
  if (!dem::avx2_in_use()) MESSAGE("no AVX2 on this processor: both runs use the baseline");
  for (int dim : {2, 3})
    for (double zeta_t : {0.0, 0.4})
      for (bool sheared : {false, true}) {
        CAPTURE(dim);
        CAPTURE(zeta_t);
        CAPTURE(sheared);
        CHECK(hash_after(dim, zeta_t, sheared, true) == hash_after(dim, zeta_t, sheared, false));
      }
}
