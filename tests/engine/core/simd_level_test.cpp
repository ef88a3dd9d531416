// The AVX-512, AVX2 and baseline kernels give the same bits: frictional contacts in 2D and 3D,
// with and without a tangential dashpot, many of them sliding, in fixed and sheared
// (Lees-Edwards) boxes.
#include <doctest/doctest.h>

#include "core/simd_level.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

uint64_t hash_with_kernels(int dim, double zeta_t, bool sheared, SimdLevel level) {
  limit_simd(level);
  auto sim = test::simulation_from(test::frictional_gas(dim, sheared ? 3.0 : 0.0, zeta_t, 0.06));
  for (int k = 0; k < 300; ++k) REQUIRE(sim->step());
  limit_simd(SimdLevel::kAvx512);
  return state_hash(sim->state());
}

}  // namespace

TEST_CASE("AVX-512, AVX2 and baseline kernels give the same bits") {
  MESSAGE("widest vector instructions of this processor: " << simd_name(simd_level()));
  for (int dim : {2, 3})
    for (double zeta_t : {0.0, 0.4})
      for (bool sheared : {false, true}) {
        CAPTURE(dim);
        CAPTURE(zeta_t);
        CAPTURE(sheared);
        const uint64_t widest = hash_with_kernels(dim, zeta_t, sheared, SimdLevel::kAvx512);
        CHECK(hash_with_kernels(dim, zeta_t, sheared, SimdLevel::kAvx2) == widest);
        CHECK(hash_with_kernels(dim, zeta_t, sheared, SimdLevel::kBaseline) == widest);
      }
}
