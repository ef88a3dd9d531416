// The hooke law with tangential history is LAMMPS's gran/hooke/history (the chute benchmark runs
// both codes on the same system), and frozen grains act as grains of infinite mass.
#include <doctest/doctest.h>

#include <cmath>

#include "silt/vec.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// Two spheres of the chute (d = 0.98, density 1.9099, k_n = 2e5, gamma_n = 50, k_t = 2/7 k_n,
// mu = 0.5) overlapping by about 1e-5 with relative normal, tangential and spin velocities.
const char* kChutePair = R"(
[scene]
dimension = 3
[domain]
lo = [-5, -5, -5]
hi = [5, 5, 5]
[contact]
model = "hooke"
k_n = 2e5
gamma_n = 50
friction = 0.5
kt_over_kn = 0.2857142857142857
[[grains]]
radius = 0.49
density = 1.9099
placement = "explicit"
positions = [[0, 0, 0], [0.97999, 0.0001, -0.00005]]
velocity = "explicit"
velocities = [[0.001, {vy}, 0.0], [-0.002, 0.0, {vz}]]
angular_velocities = [[{wx}, {wy}, {wz}], [0.0, {wy}, {wz2}]]
[run]
dt = 1e-4
)";

}  // namespace

TEST_CASE("hooke with history: a step's pair force is LAMMPS gran/hooke/history's, sticking and sliding") {
  // LAMMPS (pair gran/hooke/history, dampflag 0): with n from j to i, delta = r_i + r_j - |x_i - x_j|,
  // m* = m_i m_j / (m_i + m_j), v_r = v_i - v_j - (r_i w_i + r_j w_j) x n,
  //   F_n = (k_n delta - m* gamma_n v_r.n) n,
  //   xi += v_t dt (v_t = v_r - (v_r.n) n), F_t = -k_t xi, capped at mu |F_n| (xi rescaled),
  // torque on i: (-r_i n) x F_t. The forces of a step are evaluated at the drifted positions with
  // the half-step velocities of velocity Verlet, which the final state gives back as
  // v - (dt/2) F/m. The first evaluation (t = 0) leaves no spring, so after one step xi = v_t dt.
  // Tangential velocities and spins scaled by `scale`: k_t v_t dt is below mu F_n at 0.01 (the
  // spring sticks), far above at 1 (it slides).
  for (double scale : {0.01, 1.0}) {
    CAPTURE(scale);
    auto sim = test::simulation_from(test::fill(kChutePair, {{"vy", 0.2 * scale},
                                                             {"vz", 0.3 * scale},
                                                             {"wx", 0.2 * scale},
                                                             {"wy", -0.1 * scale},
                                                             {"wz", 0.5 * scale},
                                                             {"wz2", -0.4 * scale}}));
    REQUIRE(sim->step());
    const State& s = sim->state();
    const double dt = 1e-4, r = 0.49, pi = 3.14159265358979323846;
    const double m = 1.9099 * 4.0 / 3.0 * pi * r * r * r, inertia = 0.4 * m * r * r, m_eff = m / 2;
    auto vec = [](const std::vector<double>& a, int i) { return Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); };
    const Vec3 xi = vec(s.particle_x, 0), xj = vec(s.particle_x, 1);
    const Vec3 fi = vec(s.particle_f, 0), ti = vec(s.particle_t, 0);
    const Vec3 vi = vec(s.particle_v, 0) - 0.5 * dt * fi / m, vj = vec(s.particle_v, 1) + 0.5 * dt * fi / m;
    const Vec3 wi = vec(s.particle_w, 0) - 0.5 * dt * ti / inertia;
    const Vec3 wj = vec(s.particle_w, 1) - 0.5 * dt * vec(s.particle_t, 1) / inertia;
    const Vec3 d = xi - xj;
    const Vec3 n = d / d.norm();
    const double delta = 2 * r - d.norm();
    REQUIRE(delta > 0);
    const Vec3 vr = vi - vj - (r * wi + r * wj).cross(n);
    const double fn = 2e5 * delta - m_eff * 50 * vr.dot(n);
    const Vec3 v_t = vr - vr.dot(n) * n;
    Vec3 ft = -(2e5 * 2.0 / 7.0) * v_t * dt;
    const bool slides = ft.norm() > 0.5 * std::abs(fn);
    if (slides) ft *= 0.5 * std::abs(fn) / ft.norm();
    CHECK(slides == (scale > 0.5));  // both regimes are exercised
    const Vec3 expect = fn * n + ft;
    CHECK((fi - expect).norm() < 1e-9 * expect.norm());
    CHECK((vec(s.particle_f, 1) + expect).norm() < 1e-9 * expect.norm());  // Newton's third law
    CHECK((ti - (-r * n).cross(ft)).norm() < 1e-9 * ft.norm() * r);
    CHECK((vec(s.particle_t, 1) - (-r * n).cross(ft)).norm() < 1e-9 * ft.norm() * r);  // same lever arm
    CHECK((vec(s.pair_hist, 0) - (-ft / (2e5 * 2.0 / 7.0))).norm() < 1e-9 * v_t.norm() * dt);
  }
}

namespace {

// A grain falling on a frozen grain of the same size, and the same grain falling on a wall at the
// same height: frozen grains have infinite mass, so both contacts have m* = m and both rebounds
// follow the same law (spring_dashpot, e = 0.8 per reduced mass m*).
const char* kOnFrozen = R"(
[scene]
dimension = 3
[domain]
lo = [-2, -2, -2]
hi = [2, 2, 4]
[gravity]
magnitude = 9.81
[contact]
model = "spring_dashpot"
restitution = 0.8
contact_time = 1e-3
[[grains]]
name = "base"
radius = 0.5
frozen = true
placement = "explicit"
positions = [[0, 0, 0]]
velocity = "explicit"
velocities = [[0, 0, 0]]
[[grains]]
name = "ball"
radius = 0.5
placement = "explicit"
positions = [[0, 0, 1.2]]
[run]
dt = 1e-5
)";

const char* kOnWall = R"(
[scene]
dimension = 3
[domain]
lo = [-2, -2, -2]
hi = [2, 2, 4]
[gravity]
magnitude = 9.81
[contact]
model = "spring_dashpot"
restitution = 0.8
contact_time = 1e-3
[[walls]]
point = [0, 0, 0.5]
normal = [0, 0, 1]
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[0, 0, 1.2]]
[run]
dt = 1e-5
)";

// Steps until the ball first moves up after touching; returns its rebound speed.
double rebound(Simulation& sim, int ball) {
  double vz_min = 0;
  for (int k = 0; k < 200000; ++k) {
    REQUIRE(sim.step());
    const double vz = sim.state().particle_v[3 * ball + 2];
    vz_min = std::min(vz_min, vz);
    if (vz_min < 0 && vz > 0) {
      // Moving up, but still in contact: wait for the contact force to vanish.
      bool touching = false;
      for (double f : sim.state().particle_f) touching = touching || f != 0;
      if (!touching) return vz / -vz_min;
    }
  }
  FAIL("no rebound");
  return 0;
}

}  // namespace

TEST_CASE("a frozen grain never moves and acts as infinite mass: a grain rebounds from it as from a wall") {
  auto on_frozen = test::simulation_from(kOnFrozen);
  auto on_wall = test::simulation_from(kOnWall);
  const double e_frozen = rebound(*on_frozen, 1);
  const double e_wall = rebound(*on_wall, 0);
  CHECK(e_frozen == doctest::Approx(0.8).epsilon(2e-2));  // gravity acts during the contact too
  CHECK(e_frozen == doctest::Approx(e_wall).epsilon(1e-6));
  const State& s = on_frozen->state();
  for (int k = 0; k < 3; ++k) {
    CHECK(s.particle_x[k] == 0.0);  // the frozen grain, bit for bit where it was
    CHECK(s.particle_v[k] == 0.0);
  }
}
