// Implicit contacts (lubrication.contacts = "implicit", paste/contact_stiffness.hpp): the contact
// springs linearised into the solve, (Xi + dt K) V = F, against the explicit scheme of eq. 2.19.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "paste/contact_stiffness.hpp"
#include "paste/lubrication_laws.hpp"
#include "paste/params.hpp"
#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// Two disks of radius 1/2 overlapping by 0.01 in a liquid, nothing else acting: the contact
// spring pushes them apart against the lubrication in contact (the linear cutoff's constant
// 2 c / h_min), quasi-statically with a fixed step.
const char* kOverlappingPair = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [20, 20]
periodic = [true, true]
[contact]
model = "linear"
k_n = 1e4
friction = 0.3
kt_over_kn = 0.5
[[grains]]
radius = 0.5
density = 1.0
placement = "explicit"
positions = [[9.5, 10.0], [10.49, 10.0]]
[lubrication]
viscosity = 1.0
h_min_over_a = 1e-2
contacts = "{contacts}"
dt = {dt}
)";

double overlap(const State& s) { return 1.0 - std::abs(s.particle_x[2] - s.particle_x[0]); }

}  // namespace

TEST_CASE("implicit contacts: a spring under lubrication relaxes by the backward Euler factor, at any step") {
  // In contact xi_N = 2 c / h_min, c = (3/2) pi eta R_eq^2 with R_eq = R = 0.5 for two equal grains
  // (2 / R_eq = 1 / R_i + 1 / R_j; the solve had R / 2, a resistance 4 times too weak); the spring
  // k_n. Per step the overlap is multiplied by 1 - dt k / xi (explicit: unstable past dt = 2 xi / k)
  // or by xi / (xi + dt k) (implicit: the same fixed point, stable at every step). dt = 5 xi / k: -4
  // against 1/6.
  const double c = 1.5 * std::numbers::pi * 0.5 * 0.5, xi = 2 * c / 1e-2, k = 1e4, dt = 5 * xi / k;
  char step[64];
  std::snprintf(step, sizeof step, "%.17g", dt);
  for (const std::string contacts : {"explicit", "implicit"}) {
    CAPTURE(contacts);
    std::string s = kOverlappingPair;
    s.replace(s.find("{contacts}"), 10, contacts);
    s.replace(s.find("{dt}"), 4, step);
    auto sim = test::simulation_from(s, 1);
    sim->prepare();
    const double d0 = overlap(sim->state());
    REQUIRE(d0 == doctest::Approx(0.01).epsilon(1e-9));
    REQUIRE(sim->step());
    if (contacts == "explicit") {
      CHECK(overlap(sim->state()) == doctest::Approx(d0 * (1 - dt * k / xi)).epsilon(1e-9));  // -4 d0: thrown apart
    } else {
      double expected = d0;
      for (int n = 1; n <= 4; ++n) {
        expected *= xi / (xi + dt * k);
        CHECK(overlap(sim->state()) == doctest::Approx(expected).epsilon(1e-9));
        REQUIRE(sim->step());
      }
    }
  }
}

TEST_CASE("implicit contacts: a sticking spring adds dt k_t, one at the Coulomb limit none") {
  std::string text = kOverlappingPair;
  text.replace(text.find("{contacts}"), 10, "implicit");
  text.replace(text.find("{dt}"), 4, "0.01");
  auto sim = test::simulation_from(text, 1);
  sim->prepare();
  State s = sim->state();
  const Model& m = sim->model();
  paste::Links links;
  paste::find_connections(s, m.params.get<paste::PasteParams>().law(), links);
  REQUIRE(links.c.size() == 1);
  // The connection's resistance with R_eq = R = 0.5 (in contact: 3 pi eta R^2 / h_min).
  CHECK(links.c[0].xi_n == doctest::Approx(3 * std::numbers::pi * 0.25 / 1e-2).epsilon(1e-12));
  const double dt = 0.01, kn = 1e4, kt = 0.5 * kn, fn = kn * 0.01, limit = 0.3 * fn / kt;  // spring length at the limit
  double* hist = &s.pair_hist[2 * links.pair[0]];
  for (const double length : {0.0, 0.5 * limit, limit}) {
    CAPTURE(length);
    hist[0] = 0;
    hist[1] = length;
    paste::set_contact_stiffness(m, s, dt, links);
    CHECK(links.c[0].k_n == doctest::Approx(dt * kn).epsilon(1e-12));
    CHECK(links.c[0].k_t == (length < limit ? doctest::Approx(dt * kt).epsilon(1e-12) : doctest::Approx(0.0)));
  }
  // Apart: no stiffness.
  s.particle_x[2] += 0.02;
  paste::find_connections(s, m.params.get<paste::PasteParams>().law(), links);
  REQUIRE(links.c.size() == 1);
  paste::set_contact_stiffness(m, s, dt, links);
  CHECK(links.c[0].k_n == 0);
  CHECK(links.c[0].k_t == 0);
}

TEST_CASE("implicit contacts: the measured stresses are the imposed pressure, the contacts' increments counted") {
  // The box rows hold the contact forces plus their increment dt K G V at the imposed stresses;
  // the stress measured from the configuration's contact forces alone missed it (0.6 % in
  // paste_iso once its grains touched).
  Model m = compile(load_scene_file(test::scene_path("paste_iso"), {parse_override("lubrication.contacts=implicit")}));
  const double P = m.box_control.pressure;
  Simulation sim(std::move(m), 1);
  const Observer obs(sim.model(), {"stress.xx", "stress.yy", "p_cont_ratio", "p_lub_ratio", "n_contacts"});
  int touching = 0;
  double worst = 0, worst_sum = 0;
  for (int k = 0; k < 300; ++k) {
    REQUIRE(sim.step());
    const auto v = obs.sample(sim.model(), sim.state());
    if (v[4] == 0) continue;
    ++touching;
    worst = std::max({worst, std::abs(v[0] - P) / P, std::abs(v[1] - P) / P});
    worst_sum = std::max(worst_sum, std::abs(v[2] + v[3] - 1));
  }
  REQUIRE(touching > 50);
  // The solve's tolerance, 1e-8 of a right-hand side of the order of P times the area.
  CHECK(worst < 1e-6);
  CHECK(worst_sum < 1e-6);
}
