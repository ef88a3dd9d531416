// Velocity Verlet: ballistic paths, momentum and energy conservation.
#include <doctest/doctest.h>

#include <cmath>

#include "silt/periodic_image.hpp"
#include "support/scenes.hpp"

using namespace silt;

TEST_CASE("free fall and projectile follow x0 + v0 t + g t^2 / 2 at any dt") {
  // Velocity Verlet integrates a constant acceleration exactly: only rounding remains.
  const char* scene = R"(
[scene]
dimension = {dim}
[domain]
lo = [-100, -100, -100]
hi = [100, 100, 100]
[gravity]
magnitude = 9.81
angle = 30
[contact]
model = "hooke"
k_n = 10
[[grains]]
radius = 0.1
placement = "explicit"
positions = [[0, 0, 50]]
velocity = "explicit"
velocities = [[1.5, -0.5, 7]]
[run]
dt = {dt}
)";
  for (int dim : {2, 3}) {
    for (double dt : {1e-4, 1e-3, 1e-2}) {
      CAPTURE(dim);
      CAPTURE(dt);
      std::string text = test::fill(scene, {{"dim", dim}, {"dt", dt}});
      if (dim == 2) {
        text.replace(text.find("[-100, -100, -100]"), 18, "[-100, -100]");
        text.replace(text.find("[100, 100, 100]"), 15, "[100, 100]");
        text.replace(text.find("[[0, 0, 50]]"), 12, "[[0, 50]]");
        text.replace(text.find("[[1.5, -0.5, 7]]"), 16, "[[1.5, 7]]");
      }
      text.replace(text.find("dimension = "), 15, "dimension = " + std::to_string(dim));
      auto sim = test::simulation_from(text);
      const double T = 2.0;
      const int64_t steps = std::llround(T / dt);
      for (int64_t k = 0; k < steps; ++k) REQUIRE(sim->step());
      const State& s = sim->state();
      const Vec3 g = sim->model().gravity;
      const double x0[3] = {0, dim == 3 ? 0.0 : 50.0, 50};
      const double v0[3] = {1.5, dim == 3 ? -0.5 : 7.0, 7};
      for (int a = 0; a < dim; ++a) {
        const double expect = x0[a] + v0[a] * s.t + 0.5 * g[a] * s.t * s.t;
        CHECK(s.particle_x[a] == doctest::Approx(expect).epsilon(1e-11));
        CHECK(s.particle_v[a] == doctest::Approx(v0[a] + g[a] * s.t).epsilon(1e-11));
      }
    }
  }
}

namespace {

// A periodic gas of frictional or elastic grains.
const char* kGas = R"(
[scene]
dimension = 3
seed = 7
[domain]
lo = [0, 0, 0]
hi = [12, 12, 12]
periodic = [true, true, true]
[contact]
model = "hooke"
k_n = 1e4
gamma_n = {gamma}
friction = {mu}
[[grains]]
count = 300
radius_min = 0.4
radius_max = 0.6
placement = "random"
velocity = "gaussian"
temperature = 1.0
[run]
dt = {dt}
)";

double total_energy(const Model& m, const State& s) {
  // Kinetic energy plus the elastic energy k d^2 / 2 of the overlaps (hooke, k constant).
  double e = 0;
  for (int64_t i = 0; i < s.n; ++i) {
    for (int a = 0; a < 3; ++a) e += 0.5 * s.particle_v[3 * i + a] * s.particle_v[3 * i + a] / s.particle_inv_m[i];
    for (int a = 0; a < 3; ++a) e += 0.5 * s.particle_w[3 * i + a] * s.particle_w[3 * i + a] / s.particle_inv_i[i];
  }
  const PeriodicImage<3> img(s.box);
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      Vec3 d = at<3>(s.particle_x.data(), i) - at<3>(s.particle_x.data(), s.pair_j[p]);
      img.apply(d);
      const double overlap = s.particle_r[i] + s.particle_r[s.pair_j[p]] - d.norm();
      if (overlap > 0) e += 0.5 * m.contact.k0 * overlap * overlap;
    }
  return e;
}

}  // namespace

TEST_CASE("momentum is conserved in a periodic box (frictional, dissipative contacts)") {
  auto sim = test::simulation_from(test::fill(kGas, {{"gamma", 20.0}, {"mu", 0.5}, {"dt", 1e-3}}));
  auto momentum = [&] {
    Vec3 p = Vec3::Zero();
    double scale = 0;
    const State& s = sim->state();
    for (int64_t i = 0; i < s.n; ++i) {
      const Vec3 v = at<3>(s.particle_v.data(), i);
      p += v / s.particle_inv_m[i];
      scale += v.norm() / s.particle_inv_m[i];
    }
    return std::pair{p, scale};
  };
  const auto [p0, scale] = momentum();
  for (int k = 0; k < 4000; ++k) REQUIRE(sim->step());
  const auto [p1, unused] = momentum();
  CHECK(sim->state().nbr_builds > 10);
  CHECK((p1 - p0).norm() < 1e-12 * scale);
}

TEST_CASE("elastic collisions (e = 1) conserve energy over many collisions") {
  // t_c = pi sqrt(m*/k) ~ 0.0095 for the smallest pair; dt = 1e-4 resolves every contact with
  // about 100 steps, and velocity Verlet's energy error does not drift.
  auto sim = test::simulation_from(test::fill(kGas, {{"gamma", 0.0}, {"mu", 0.0}, {"dt", 1e-4}}));
  sim->prepare();
  const double e0 = total_energy(sim->model(), sim->state());
  // Count collisions as the times a grain goes from no contact to some contact (sampled every
  // 10 steps, well below the contact duration of ~100 steps).
  int64_t collisions = 0;
  std::vector<uint8_t> was(sim->state().n, 0);
  for (int k = 0; k < 30000; ++k) {
    REQUIRE(sim->step());
    if (k % 10 == 0) {
      const State& s = sim->state();
      std::vector<uint8_t> now(s.n, 0);
      for (int64_t i = 0; i < s.n; ++i)
        for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p)
          if (s.pair_f[3 * p] != 0 || s.pair_f[3 * p + 1] != 0 || s.pair_f[3 * p + 2] != 0)
            now[i] = now[s.pair_j[p]] = 1;
      for (int64_t i = 0; i < s.n; ++i) collisions += now[i] && !was[i];
      was.swap(now);
    }
  }
  const double e1 = total_energy(sim->model(), sim->state());
  CHECK(collisions > 1000);
  CHECK(std::abs(e1 - e0) < 2e-4 * e0);
}
