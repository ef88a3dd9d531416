// Coordination of a contact network built by hand: z, Peyneau's z* = z/(1 - p0) and p_n, and the
// mechanical skeleton z_mech, as measurements and as observables.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <string>
#include <vector>

#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 14 disks of radius 0.5 in an open box, centres 0.99 apart where they touch (overlap 2 % of the
// radius):
//  - a hexagon around a centre grain (grain 0: 6 contacts; grains 1-6: 3 each, the centre and
//    two ring neighbours), and grain 7 touching ring grain 1 only (grain 1: 4 contacts);
//  - a triangle (grains 8, 9, 10: 2 contacts each, 10 has a third) and grain 11 on top of 10
//    only;
//  - grains 12 and 13 far from everything (no contact).
// Contacts per grain: 6, 4, 3, 3, 3, 3, 3, 1, 2, 2, 3, 1, 0, 0: 34 in all for 14 grains.
const char* kCluster = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [20, 20]
[contact]
model = "linear"
k_n = 1e3
damping = 0.5
friction = {mu}
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[5, 5], [5.99, 5], [5.495, 5.857365], [4.505, 5.857365], [4.01, 5], [4.505, 4.142635],
             [5.495, 4.142635], [6.98, 5],
             [12, 12], [12.99, 12], [12.495, 12.857365], [12.495, 13.847365],
             [2, 17], [17, 2]]
[run]
dt = 1e-3
)";

double observe(const Model& m, const State& s, const std::string& name) { return Observer(m, {name}).sample(m, s)[0]; }

}  // namespace

TEST_CASE("coordination of a hand-built network: z, z* = z/(1 - p0), p_n and the mechanical skeleton") {
  for (double mu : {0.0, 0.3}) {
    CAPTURE(mu);
    auto sim = test::simulation_from(test::fill(kCluster, {{"mu", mu}}));
    sim->prepare();  // lists and forces at t = 0, no motion
    const Model& m = sim->model();
    const State& s = sim->state();
    const Measurements q = measure(m, s);
    CHECK(q.n_contacts == 17);
    CHECK(q.z == doctest::Approx(34.0 / 14));
    // Peyneau: rattlers are the grains with no contact (12 and 13).
    CHECK(q.p0 == doctest::Approx(2.0 / 14));
    CHECK(q.z_star == doctest::Approx(34.0 / 12));
    const std::vector<double> pn = {2, 2, 2, 6, 1, 0, 1};  // grains with n = 0 .. 6 contacts
    REQUIRE(q.pn.size() == pn.size());
    for (size_t n = 0; n < pn.size(); ++n) CHECK(q.pn[n] == doctest::Approx(pn[n] / 14));
    // Mechanical skeleton. Frictionless disks need D + 1 = 3 contacts: 7, 11, 12 and 13 go, then
    // ring grain 1 is back to 3 and stays; the triangle goes grain by grain (8 and 9 at once,
    // then 10, left with none). What remains is the hexagon: 6 + 6 x 3 = 24 contacts on 7 grains.
    // With friction 2 contacts suffice: 7, 11, 12, 13 go and the triangle stays (6 on 3 more).
    if (mu == 0) {
      CHECK(q.z_mech == doctest::Approx(24.0 / 7));
      CHECK(q.n_off_skeleton == 7);
    } else {
      CHECK(q.z_mech == doctest::Approx(30.0 / 10));
      CHECK(q.n_off_skeleton == 4);
    }
    // The same as observables; pn.K beyond the largest count is 0.
    CHECK(observe(m, s, "z") == q.z);
    CHECK(observe(m, s, "z_star") == q.z_star);
    CHECK(observe(m, s, "z_mech") == q.z_mech);
    CHECK(observe(m, s, "p0") == q.p0);
    CHECK(observe(m, s, "pn.0") == q.p0);
    CHECK(observe(m, s, "pn.3") == doctest::Approx(6.0 / 14));
    CHECK(observe(m, s, "pn.6") == doctest::Approx(1.0 / 14));
    CHECK(observe(m, s, "pn.7") == 0);
    CHECK(observe(m, s, "pn.120") == 0);
  }
}

TEST_CASE("connectivity observable names: pn.K with a count K, apart from the grain syntax p[K].x") {
  const Model m = test::model_from(test::fill(kCluster, {{"mu", 0.0}}));
  for (const char* good : {"pn.0", "pn.4", "pn.12", "pn.999", "p0", "z_mech", "p[0].x"}) {
    CAPTURE(good);
    CHECK(check_observable(good, m).empty());
  }
  for (const char* bad : {"pn.", "pn.x", "pn.-1", "pn.1000", "pn", "p1"}) {
    CAPTURE(bad);
    CHECK(!check_observable(bad, m).empty());
  }
  const auto names = observable_names(m);
  for (const char* listed : {"z_star", "z_mech", "p0", "pn.0", "pn.12"}) {
    CAPTURE(listed);
    CHECK(std::count(names.begin(), names.end(), listed) == 1);
  }
}

TEST_CASE("the velocity profile skips a grain it cannot place (a failed run's NaN, a far position)") {
  auto sim = test::simulation_from(test::fill(kCluster, {{"mu", 0.3}}));
  const Model& m = sim->model();
  State s = sim->state();
  s.particle_v[0] = 1.0;
  s.particle_x[2 * 1 + 1] = std::nan("");  // grain 1: its y
  s.particle_x[2 * 2 + 1] = 1e300;         // grain 2: far above the box
  s.particle_r[3] = 1e300;                 // grain 3: covers every slab
  const VelocityProfile p = velocity_profile(m, s, 10);
  int64_t counted = 0;
  for (int k = 0; k < 10; ++k) {
    CHECK(std::isfinite(p.vx[k]));
    counted += p.count[k];
  }
  CHECK(counted >= 11);  // the other grains, each in one or two slabs, and grain 3 in every slab
  CHECK(p.count[9] >= 1);
}

TEST_CASE("the measurements' parts, asked one by one in any order and again, are those of all at once") {
  using namespace measure_part;
  auto sim = test::simulation_from(test::fill(kCluster, {{"mu", 0.3}}));
  for (int k = 0; k < 20; ++k) REQUIRE(sim->step());  // forces, stresses and springs not zero
  const Model& m = sim->model();
  const State& s = sim->state();
  const Measurements all = measure(m, s);
  REQUIRE(all.n_contacts > 0);
  REQUIRE(all.e_contact > 0);
  REQUIRE(all.n_off_skeleton > 0);
  auto check_same = [](const Measurements& a, const Measurements& b) {
    CHECK(a.ke == b.ke);
    CHECK(a.ke_rot == b.ke_rot);
    CHECK(a.ke_fluct == b.ke_fluct);
    CHECK(a.phi == b.phi);
    CHECK(a.volume == b.volume);
    CHECK(a.max_net_force == b.max_net_force);
    CHECK(a.momentum == b.momentum);
    CHECK(a.stress == b.stress);
    CHECK(a.stress_pairs == b.stress_pairs);
    CHECK(a.pressure == b.pressure);
    CHECK(a.n_contacts == b.n_contacts);
    CHECK(a.fabric == b.fabric);
    CHECK(a.z == b.z);
    CHECK(a.z_star == b.z_star);
    CHECK(a.p0 == b.p0);
    CHECK(a.pn == b.pn);
    CHECK(a.z_mech == b.z_mech);
    CHECK(a.n_off_skeleton == b.n_off_skeleton);
    CHECK(a.e_contact == b.e_contact);
  };
  const std::vector<std::vector<unsigned>> orders = {{kGrains, kStress, kContacts, kSkeleton, kEnergy},
                                                     {kEnergy, kSkeleton, kContacts, kStress, kGrains},
                                                     {kSkeleton, kGrains | kEnergy, kContacts | kStress}};
  for (const auto& order : orders) {
    ObservableContext c(m, s);
    for (unsigned part : order) {
      c.meas(part);
      c.meas(part);  // again: nothing counted twice
    }
    check_same(c.meas(kAll), all);
  }
  // A part not asked stays at its defaults.
  const Measurements contacts = measure(m, s, kContacts);
  CHECK(contacts.n_contacts == all.n_contacts);
  CHECK(contacts.z_mech == 0);
  CHECK(contacts.e_contact == 0);
  CHECK(contacts.ke == 0);
}

TEST_CASE("the contacts of 6,400 disks on a square lattice, walked in blocks on one and on two threads") {
  // Each disk touches its four neighbours (spacing 1, radius 0.51): z = z* = z_mech = 4, p0 = 0, and
  // half the contacts along x, half along y: the fabric diag(1/2, 1/2), exactly, however the
  // blocks of the walk fall among the threads.
  const char* kSquare = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [80, 80]
periodic = [true, true]
[contact]
model = "hooke"
k_n = 1e4
friction = 0.3
[[grains]]
radius = 0.51
placement = "lattice"
lattice = "sc"
spacing = 1.0
lattice_origin = [0.5, 0.5]
[run]
dt = 1e-4
)";
  auto sim = test::simulation_from(kSquare, 1);
  sim->prepare();
  REQUIRE(sim->state().n == 6400);
  for (int threads : {1, 2}) {
    CAPTURE(threads);
    Measurements out;
    tbb::task_arena(threads).execute([&] { out = measure(sim->model(), sim->state()); });
    CHECK(out.n_contacts == 12800);
    CHECK(out.z == 4.0);
    CHECK(out.z_star == 4.0);
    CHECK(out.z_mech == 4.0);
    CHECK(out.p0 == 0.0);
    CHECK(out.n_off_skeleton == 0);
    CHECK(out.fabric[0][0] == 0.5);
    CHECK(out.fabric[1][1] == 0.5);
    CHECK(out.fabric[0][1] == 0.0);
  }
}
