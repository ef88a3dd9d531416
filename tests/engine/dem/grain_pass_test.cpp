// The grain passes of velocity Verlet (the half kicks and the drift) run four grains per AVX2
// instruction where the processor has it (grain_pass_avx2.hpp) and one at a time otherwise: both
// give the same bits, on any number of threads, with frozen grains among the moving ones in every
// lane, grains crossing the periodic faces, a count that leaves a tail of scalar grains, with and
// without friction (torques), in 2D and 3D, in a still box, under Lees-Edwards shear and with a
// stress-controlled length; and a grain whose velocity goes to infinity names the same grain.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/simd_level.hpp"
#include "silt/state.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 211 moving grains in a periodic box under tilted gravity: fast enough that grains cross the
// faces every few steps.
const char* kMixed = R"(
[scene]
dimension = {dim}
seed = 11
[domain]
lo = LO
hi = HI
periodic = PER
[gravity]
magnitude = 1
angle = 30
[contact]
model = "hooke"
k_n = 3e4
gamma_n = 10
friction = {mu}
[[grains]]
count = 211
radius_min = 0.3
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 2.0
[run]
dt = 1e-3
)";

// The frozen grains of the still box.
const char* kFrozen = R"(
[[grains]]
count = 40
radius = 0.4
frozen = true
placement = "random"
velocity = "gaussian"
temperature = 1.0
)";

struct Outcome {
  uint64_t hash = 0;
  int64_t failed_step = -1, particle = -1;
};

// `steps` steps; before step `blow_at` (if >= 0) the velocity of grain `blow` is set to infinity,
// or its angular velocity (spin), which only the second half kick's check sees without friction.
// flow: "" (the box still, 40 frozen grains among the others), "shear" (Lees-Edwards at a fixed
// rate) or "stress" (sheared too, L_y held at a pressure: the affine flow stretches the grains).
// A deforming box holds no frozen grains.
Outcome run(int dim, const std::string& flow, double mu, int threads, int steps, int64_t blow = -1, int blow_at = -1,
            bool spin = false) {
  const bool d3 = dim == 3;
  const std::string scene = test::with_lists(kMixed, d3 ? "[0, 0, 0]" : "[0, 0]", d3 ? "[9, 8, 7]" : "[30, 26]",
                                             d3 ? "[true, true, true]" : "[true, true]");
  std::string text = test::fill(scene, {{"dim", dim}, {"mu", mu}});
  // (gravity along the length a pressure holds is refused: nothing would hold the grains)
  if (flow == "stress" && !d3) text.replace(text.find("magnitude = 1\nangle = 30"), 24, "vector = [0.5, 0.0]");
  if (flow.empty()) text += kFrozen;
  else text += "[shear]\nrate = 0.7\n";
  if (flow == "stress")
    text += d3 ? "[box]\npressure = 2.0\ncontrolled = [false, true, false]\n"
               : "[box]\npressure = 2.0\ncontrolled = [false, true]\n";
  auto sim = test::simulation_from(text, threads);
  const int64_t last_v = dim - 1, last_w = d3 ? 2 : 0;  // a grain's last velocity and spin components
  Outcome out;
  for (int k = 0; k < steps; ++k) {
    if (k == blow_at)
      (spin ? sim->state().particle_w[(d3 ? 3 : 1) * blow + last_w] : sim->state().particle_v[dim * blow + last_v]) =
          std::numeric_limits<double>::infinity();
    if (!sim->step()) {
      out.failed_step = k;
      out.particle = sim->state().failure.particle;
      break;
    }
  }
  out.hash = state_hash(sim->state());
  return out;
}

}  // namespace

TEST_CASE("the grain passes give the same bits at every vector level and thread count") {
  const int steps = test::compared_steps(1500);
  for (int dim : {2, 3})
    for (const std::string flow : {"", "shear", "stress"})
      for (double mu : {0.0, 0.5}) {
        CAPTURE(dim);
        CAPTURE(flow);
        CAPTURE(mu);
        limit_simd(SimdLevel::kBaseline);
        const Outcome ref = run(dim, flow, mu, 1, steps);
        const Outcome ref_blow = run(dim, flow, mu, 1, 50, 37, 20), ref_spin = run(dim, flow, mu, 1, 50, 90, 20, true);
        REQUIRE(ref.failed_step == -1);
        REQUIRE(ref_blow.failed_step == 20);
        REQUIRE(ref_spin.failed_step == 20);
        for (SimdLevel level : {SimdLevel::kAvx512, SimdLevel::kAvx2, SimdLevel::kBaseline}) {
          limit_simd(level);
          CAPTURE(simd_name(level));
          for (int threads : {1, 2}) {
            CAPTURE(threads);
            CHECK(run(dim, flow, mu, threads, steps).hash == ref.hash);
            const Outcome blow = run(dim, flow, mu, threads, 50, 37, 20);
            CHECK(blow.failed_step == ref_blow.failed_step);
            CHECK(blow.particle == ref_blow.particle);
            CHECK(blow.hash == ref_blow.hash);
            const Outcome spin = run(dim, flow, mu, threads, 50, 90, 20, true);
            CHECK(spin.failed_step == ref_spin.failed_step);
            CHECK(spin.particle == ref_spin.particle);
            CHECK(spin.hash == ref_spin.hash);
          }
        }
      }
  limit_simd(SimdLevel::kAvx512);
}
