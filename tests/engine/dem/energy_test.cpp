// The energies and the momentum of the grains: e_contact keeps ke + e_contact constant through
// elastic collisions (linear and Hertz), momentum is conserved, and the elastic energies are the
// integrals of the forces.
#include <doctest/doctest.h>

#include <cmath>

#include "dem/contact_laws.hpp"
#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// Two spheres approaching head-on (no gravity, no dashpot), with a glancing offset so that the
// tangential spring works too; frictional.
const char* kGlancingPair = R"(
[scene]
dimension = 3
[domain]
lo = [-5, -5, -5]
hi = [5, 5, 5]
[contact]
{law}
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[-1, 0.3, 0], [1, -0.3, 0]]
velocity = "explicit"
velocities = [[1, 0, 0], [-1, 0, 0]]
[run]
dt = 1e-5
)";

}  // namespace

TEST_CASE("energy: ke + e_contact is constant through an elastic collision, and momentum is conserved") {
  // Frictional linear springs; Hertz without friction: a tangential spring whose stiffness follows
  // K_N(h) stores more or less than the work done on it as h changes (the incremental law is not
  // a potential), so Hertz's e_contact is exact for the normal part only.
  for (std::string law :
       {"model = \"linear\"\nk_n = 1e5\nfriction = 0.5", "model = \"hertz\"\nyoung_modulus = 1e7\nfriction = 0"}) {
    CAPTURE(law);
    std::string text = kGlancingPair;
    text.replace(text.find("{law}"), 5, law);
    auto sim = test::simulation_from(text, 1);
    const Observer obs(sim->model(), {"ke", "e_contact", "momentum.x", "momentum.y", "n_contacts"});
    const double e0 = obs.sample(sim->model(), sim->state())[0];
    double worst = 0, peak = 0;
    int64_t touching = 0;
    for (int k = 0; k < 200000; ++k) {
      REQUIRE(sim->step());
      const auto v = obs.sample(sim->model(), sim->state());
      worst = std::max(worst, std::abs(v[0] + v[1] - e0) / e0);
      peak = std::max(peak, v[1] / e0);
      touching += v[4] > 0;
      CHECK(std::abs(v[2]) < 1e-12);
      CHECK(std::abs(v[3]) < 1e-12);
      if (touching > 0 && v[4] == 0) break;  // apart again
    }
    CHECK(touching > 100);
    CHECK(peak > 0.3);    // a good part of the energy went into the springs
    CHECK(worst < 2e-3);  // and came back (velocity Verlet, second order in dt)
  }
}

TEST_CASE("energy: the elastic energies are the integrals of the forces") {
  ContactParams lin;
  lin.law = NormalLaw::kLinear;
  lin.k0 = 3e4;
  ContactParams hz;
  hz.law = NormalLaw::kHertz;
  hz.e_tilde = 2e9;
  for (const ContactParams& p : {lin, hz}) {
    const double r_eq = 0.01, h = 2e-4;
    // Simpson's rule on F(h) = normal_force(h, no rate).
    const int n = 2000;
    double integral = 0;
    for (int k = 0; k <= n; ++k) {
      const double x = h * k / n;
      const double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
      integral += w * dem::normal_force(p, 1.0, r_eq, x, 0.0).fn;
    }
    integral *= h / n / 3;
    CHECK(dem::normal_elastic_energy(p, 1.0, r_eq, h) == doctest::Approx(integral).epsilon(1e-6));
    CHECK(dem::normal_elastic_energy(p, 1.0, r_eq, -1e-3) == 0);
  }
}
