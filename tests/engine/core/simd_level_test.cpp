// The AVX2 kernels and the baseline ones give the same bits: frictional contacts in 2D and 3D,
// with and without a tangential dashpot, many of them sliding, in fixed and sheared
// (Lees-Edwards) boxes.
#include <doctest/doctest.h>

#include "core/simd_level.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

uint64_t hash_with_kernels(int dim, double zeta_t, bool sheared, bool baseline) {
  limit_to_baseline(baseline);
  auto sim = test::simulation_from(test::frictional_gas(dim, sheared ? 3.0 : 0.0, zeta_t, 0.06));
  for (int k = 0; k < 300; ++k) REQUIRE(sim->step());
  limit_to_baseline(false);
  return state_hash(sim->state());
}

}  // namespace

TEST_CASE("AVX2 and baseline kernels give the same bits") {
  if (!avx2_in_use()) MESSAGE("no AVX2 on this processor: both runs use the baseline");
  for (int dim : {2, 3})
    for (double zeta_t : {0.0, 0.4})
      for (bool sheared : {false, true}) {
        CAPTURE(dim);
        CAPTURE(zeta_t);
        CAPTURE(sheared);
        CHECK(hash_with_kernels(dim, zeta_t, sheared, true) == hash_with_kernels(dim, zeta_t, sheared, false));
      }
}
