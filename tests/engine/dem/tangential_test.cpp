// Tangential spring with Coulomb cap: stick then slip, and grains on a plane.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "dem/contact_laws.hpp"
#include "silt/text.hpp"
#include "support/scenes.hpp"

using namespace silt;

TEST_CASE("tangential spring: elastic while |F_t| < mu F_n, then slides at mu F_n") {
  // Constant slip velocity along x on a contact of normal z: F_t = -k_t v t until it reaches
  // mu F_n, then stays there; reversing the slip unloads elastically.
  const Vec3 n(0, 0, 1), vt(0.1, 0, 0);
  Vec3 xi = Vec3::Zero();
  const double kt = 1000, mu_fn = 0.5, dt = 1e-3;
  double t = 0;
  for (int k = 1; k <= 100; ++k) {
    const Vec3 f = dem::tangential_force(xi, n, vt, dt, kt, mu_fn);
    t += dt;
    const double elastic = kt * 0.1 * t;
    if (elastic < mu_fn - 1e-12) {
      CHECK(f.x() == doctest::Approx(-elastic));  // stick
    } else {
      CHECK(f.x() == doctest::Approx(-mu_fn));       // slide
      CHECK(xi.x() == doctest::Approx(mu_fn / kt));  // spring held at the Coulomb limit
    }
    CHECK(f.y() == 0);
    CHECK(f.z() == 0);
  }
  // Reverse: the force decreases elastically from mu F_n.
  const Vec3 f1 = dem::tangential_force(xi, n, Vec3(-0.1, 0, 0), dt, kt, mu_fn);
  CHECK(f1.x() == doctest::Approx(-mu_fn + kt * 0.1 * dt));
  // The elongation stays in the tangent plane when the normal turns.
  Vec3 e(0.1, 0, 0.05);
  dem::tangential_force(e, n, Vec3(Vec3::Zero()), dt, kt, 1e9);
  CHECK(e.z() == 0);
}

TEST_CASE("tangential spring with a dashpot: F_t = -k_t xi - c_t v_t, and the spring holds the rest at the cap") {
  const Vec3 n(0, 0, 1), vt(0.2, -0.1, 0);
  const double kt = 1000, ct = 5, dt = 1e-3;
  // Sticking: the dashpot adds to the spring.
  Vec3 xi(1e-4, 0, 0);
  const Vec3 f = dem::tangential_force(xi, n, vt, dt, kt, 1e9, ct);
  const Vec3 xi_expect = Vec3(1e-4, 0, 0) + vt * dt;
  CHECK((xi - xi_expect).norm() < 1e-15);
  CHECK((f - (-kt * xi_expect - ct * vt)).norm() < 1e-12);
  // Sliding: |F_t| = mu F_n along the same direction, the spring elongation is what is left once
  // the dashpot has taken its part.
  const double mu_fn = 0.3;
  Vec3 xs(2e-3, 1e-3, 0);
  const Vec3 free = -kt * (Vec3(2e-3, 1e-3, 0) + vt * dt) - ct * vt;
  const Vec3 fs = dem::tangential_force(xs, n, vt, dt, kt, mu_fn, ct);
  CHECK(fs.norm() == doctest::Approx(mu_fn));
  CHECK((fs.normalized() - free.normalized()).norm() < 1e-12);
  CHECK((xs - (-(fs + ct * vt) / kt)).norm() < 1e-15);
  // No friction force at all when mu F_n = 0, and no NaN from a zero force.
  Vec3 x0 = Vec3::Zero();
  const Vec3 f0 = dem::tangential_force(x0, n, Vec3(Vec3::Zero()), dt, kt, 0.0, ct);
  CHECK(f0.norm() == 0);
  CHECK(x0.norm() == 0);
}

namespace {

// A grain on a horizontal frictional wall, gravity tilted by `angle`: an incline of that angle.
const char* kIncline = R"(
[scene]
dimension = {dim}
[domain]
lo = LO
hi = HI
[gravity]
magnitude = 9.81
angle = {angle}
[contact]
model = "spring_dashpot"
restitution = 0.5
contact_time = 1e-4
friction = {mu}
kt_over_kn = 0.5
[[walls]]
point = PT
normal = NRM
[[grains]]
radius = 0.005
density = 2500
placement = "explicit"
positions = POS
velocity = "explicit"
velocities = VEL
[run]
dt = 1e-6
)";

std::string incline_scene(int dim, double angle, double mu, double v0) {
  const double r = 0.005;
  // Start resting on the wall: the weight overlap m g / k_n is about 1e-7 r here.
  std::string s = test::fill(kIncline, {{"angle", angle}, {"mu", mu}});
  s.replace(s.find("dimension = {dim}"), 17, "dimension = " + std::to_string(dim));
  auto put = [&](const char* key, const std::string& v) { s.replace(s.find(key), std::string(key).size(), v); };
  const std::string z = std::to_string(r - 1e-9);
  const std::string vx = format_number(v0, 17);
  if (dim == 3) {
    put("LO", "[-10, -1, 0]");
    put("HI", "[10, 1, 1]");
    put("PT", "[0, 0, 0]");
    put("NRM", "[0, 0, 1]");
    put("POS", "[[0, 0, " + z + "]]");
    put("VEL", "[[" + vx + ", 0, 0]]");
  } else {
    put("LO", "[-10, 0]");
    put("HI", "[10, 1]");
    put("PT", "[0, 0]");
    put("NRM", "[0, 1]");
    put("POS", "[[0, " + z + "]]");
    put("VEL", "[[" + vx + ", 0]]");
  }
  return s;
}

std::unique_ptr<Simulation> incline(int dim, double angle, double mu, double v0) {
  return test::simulation_from(incline_scene(dim, angle, mu, v0));
}

}  // namespace

TEST_CASE("a disk and a sphere roll without slipping down an incline: a = g sin(theta) / (1 + I/(m r^2))") {
  const double theta = 20, g = 9.81, pi = 3.14159265358979323846;
  const double s = std::sin(theta * pi / 180);
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    const double k = dim == 2 ? 0.5 : 0.4;     // I / (m r^2): disk, sphere
    auto sim = incline(dim, theta, 0.5, 0.0);  // mu = 0.5 > tan(theta) k / (1 + k)
    for (int i = 0; i < 200000; ++i) REQUIRE(sim->step());
    const State& st = sim->state();
    const double t = st.t;
    const double a = st.particle_v[0] / t;
    CHECK(a == doctest::Approx(g * s / (1 + k)).epsilon(2e-3));
    // Rolling: the contact point does not slip, v = -w r (w about -y in 3D, about z in 2D).
    const double w = dim == 3 ? st.particle_w[1] : st.particle_w[0];
    const double roll = dim == 3 ? w * 0.005 : -w * 0.005;
    CHECK(roll == doctest::Approx(st.particle_v[0]).epsilon(2e-3));
  }
}

TEST_CASE("below the friction needed to roll, the grain slides with a = g (sin - mu cos)") {
  const double theta = 30, g = 9.81, pi = 3.14159265358979323846, mu = 0.1;
  const double s = std::sin(theta * pi / 180), c = std::cos(theta * pi / 180);
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    const double k = dim == 2 ? 0.5 : 0.4;
    auto sim = incline(dim, theta, mu, 0.0);  // needs mu >= tan(30) k/(1+k) ~ 0.19 to roll
    for (int i = 0; i < 100000; ++i) REQUIRE(sim->step());
    const State& st = sim->state();
    CHECK(st.particle_v[0] / st.t == doctest::Approx(g * (s - mu * c)).epsilon(2e-3));
    // Friction mu m g cos spins the grain up: dw/dt = mu g cos / (k r).
    const double w = dim == 3 ? st.particle_w[1] : -st.particle_w[0];
    CHECK(w / st.t == doctest::Approx(mu * g * c / (k * 0.005)).epsilon(2e-3));
  }
}

TEST_CASE("a grain launched sliding on a flat wall slips, then rolls at v0 / (1 + k)") {
  // Coulomb friction decelerates at mu g while spinning the grain up; rolling starts when
  // v = w r, at v = v0 / (1 + I/(m r^2)): 2/3 v0 for a disk, 5/7 v0 for a sphere.
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    const double k = dim == 2 ? 0.5 : 0.4;
    auto sim = incline(dim, 0, 0.3, 0.2);
    const double v0 = 0.2, g = 9.81;
    // Sliding phase: deceleration mu g.
    for (int i = 0; i < 5000; ++i) REQUIRE(sim->step());
    const double t1 = sim->state().t;
    CHECK((v0 - sim->state().particle_v[0]) / t1 == doctest::Approx(0.3 * g).epsilon(1e-2));
    // Rolling after t = v0 k / ((1 + k) mu g) ~ 0.02 s.
    for (int i = 0; i < 100000; ++i) REQUIRE(sim->step());
    CHECK(sim->state().particle_v[0] == doctest::Approx(v0 / (1 + k)).epsilon(2e-3));
  }
}

TEST_CASE("the time step's stability limit is the tangential spring's when it is the faster mode") {
  // A grain stuck to a wall by friction (mu = 10) with k_t = 10 k_n: the tangential spring moves it
  // and turns it, stiffness k_t (1 + m r^2 / I), 3 k_t for a disk and 3.5 k_t for a sphere. Its
  // limit 2 / sqrt(that / m) is sqrt(30) or sqrt(35) times shorter than the normal spring's. Nudged
  // along the wall by 1e-7 m/s, the grain oscillates at that speed 10 % under the limit, and the
  // oscillation grows without bound 10 % over it (by 2.4 a step; the Coulomb cap stops it at about
  // mu g dt (1 + m r^2 / I) ~ 1e-3 m/s).
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    const double turn = dim == 2 ? 3.0 : 3.5, v0 = 1e-7, r = 0.005;
    std::string s = incline_scene(dim, 0, 10, v0);
    s.replace(s.find("kt_over_kn = 0.5"), 16, "kt_over_kn = 10");
    auto sim = test::simulation_from(s);
    const Model& m = sim->model();
    REQUIRE(m.dt_stable_tangential);
    const double k = dem::spring_dashpot_rates(0.5, 1e-4).k;  // k_n / m*
    CHECK(m.dt_stable == doctest::Approx(2 / std::sqrt(turn * 10 * k)).epsilon(1e-12));
    CHECK(describe(m).find("its tangential spring") != std::string::npos);
    for (double f : {0.9, 1.1}) {
      CAPTURE(f);
      auto run = test::simulation_from(s);
      run->model_for_steering().dt = f * m.dt_stable;
      double largest = 0;
      for (int i = 0; i < 400; ++i) {
        REQUIRE(run->step());
        const State& st = run->state();
        const double spin = dim == 3 ? st.particle_w[1] : -st.particle_w[0];
        largest = std::max(largest, std::abs(st.particle_v[0] - spin * r));  // the contact point's slip
      }
      if (f < 1) CHECK(largest < 10 * v0);
      else CHECK(largest > 1000 * v0);
    }
    // A scene asking for a step past it is refused, naming the ratio that made the mode the faster.
    std::string past = s;
    past.replace(past.find("dt = 1e-6"), 9, "dt = " + format_number(1.1 * m.dt_stable, 17));
    const std::string err = test::scene_error(past);
    CHECK(err.find("tangential spring") != std::string::npos);
    CHECK(err.find("contact.kt_over_kn") != std::string::npos);
    // The default step (no run.dt) past a limit that a strong tangential dashpot shortened: located
    // at the dashpot (it was at the [run] table, which gives no step).
    std::string damped = incline_scene(dim, 0, 10, v0);
    damped.replace(damped.find("kt_over_kn = 0.5"), 16, "kt_over_kn = 0.5\ntangential_damping = 10");
    damped.replace(damped.find("dt = 1e-6"), 9, "steps = 1");
    const std::string at = test::scene_error(damped);
    CHECK(at.find(":16:22: time step") != std::string::npos);
    CHECK(at.find("(the default) exceeds") != std::string::npos);
    CHECK(at.find("give run.dt_over_tc below ") != std::string::npos);
  }
}
