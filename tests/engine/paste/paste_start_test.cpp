// A paste started from a packing compressed dry (prepare.compress, or a packing given to a run):
// its first drift moves the grains with the paste's own solved velocities, not the compression's,
// and the springs that hold the packing are kept.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "paste/params.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// 80 frictional disks at an imposed pressure P = 1, compressed dry first, then dilated by
// `dilation` (1: the static packing, its contacts held by their springs); viscosity eta.
Model prepared(double eta, double dilation = 1.05) {
  return test::model_from(
      test::paste_disks({.n = 80, .L = 10, .h_min = 1e-3, .viscosity = eta, .dilation = dilation, .seed = 11}));
}

std::vector<double> sorted_magnitudes(const std::vector<double>& v) {
  std::vector<double> out;
  for (double x : v)
    if (x != 0) out.push_back(std::abs(x));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("paste: a packing compressed dry starts from the paste's velocities, the same in units of eta / P") {
  // Quasi-static, the paste's trajectory in units of eta / P does not depend on eta. Before the
  // paste solved the first state of a prepared packing, the first drift moved the grains with the
  // compression's velocities for dt_initial = 1e-3 eta / P: at eta = 1e10 they overlapped by 83 %.
  const State packing = prepare_packing(prepared(1), 1, nullptr, nullptr);
  std::vector<double> phi, time;
  for (double eta : {1.0, 1e10}) {
    CAPTURE(eta);
    const Model m = prepared(eta);
    Simulation sim(m, 1);
    sim.restore(packing);
    for (int k = 0; k < 10; ++k) REQUIRE(sim.step());
    phi.push_back(measure(m, sim.state()).phi);
    time.push_back(sim.state().t / eta);
  }
  CHECK(phi[1] == doctest::Approx(phi[0]).epsilon(1e-9));
  CHECK(time[1] == doctest::Approx(time[0]).epsilon(1e-9));
  CHECK(phi[0] != doctest::Approx(measure(prepared(1), packing).phi).epsilon(1e-6));  // the grains moved
}

TEST_CASE(
    "paste: the first state's solve keeps the springs of a prepared packing, and a continued run is not restarted") {
  const Model m = prepared(1, 1.0);
  const State packing = prepare_packing(m, 1, nullptr, nullptr);
  const std::vector<double> before = sorted_magnitudes(packing.pair_hist);
  REQUIRE(!before.empty());  // friction holds the packing
  Simulation sim(m, 1);
  sim.restore(packing);
  sim.prepare();
  // The same springs (a rebuilt pair list may hold them in another order).
  CHECK(sorted_magnitudes(sim.state().pair_hist) == before);
  // A state the paste has stepped continues as it is: the same bits as the run that made it.
  for (int k = 0; k < 4; ++k) REQUIRE(sim.step());
  const State mid = sim.state();
  for (int k = 0; k < 4; ++k) REQUIRE(sim.step());
  Simulation again(m, 1);
  again.restore(mid);
  for (int k = 0; k < 4; ++k) REQUIRE(again.step());
  CHECK(state_hash(again.state()) == state_hash(sim.state()));
}

TEST_CASE(
    "paste: sheared or cycled faster than its pressure (Vi > 1), the first step is 1e-3 of the shear or cycle time") {
  // At Vi = 1e3 the default first step was 1e-3 eta / P, a strain of 1 in one step: the grains
  // passed through each other at step 1 (an overlap of 67 % in paste_shear). Now it is 1e-3 /
  // gammadot, and the adaptive step grows from there.
  const State packing = prepare_packing(prepared(1), 1, nullptr, nullptr);
  for (double vi : {1e-2, 1e3}) {
    CAPTURE(vi);
    const Model m =
        test::model_from(test::paste_disks({.n = 80, .L = 10, .h_min = 1e-3, .dilation = 1.05, .seed = 11}) +
                         "[shear]\nviscous_number = " + std::to_string(vi) + "\n");
    const double rate = vi;  // gammadot = Vi P / eta, P = eta = 1
    CHECK(m.params.get<paste::PasteParams>().dt_initial == doctest::Approx(1e-3 * std::min(1.0, 1 / rate)));
    Simulation sim(m, 1);
    sim.restore(packing);
    for (int k = 0; k < 30; ++k) REQUIRE(sim.step());
    CHECK(sim.state().shear_strain > 0);
  }
  // Stress cycles of w = Vi P / eta = 1e3: the first step is 1e-3 / w.
  std::string cycles = test::paste_disks({.n = 80, .L = 10, .h_min = 1e-3, .seed = 11});
  cycles.replace(cycles.find("pressure = 1.0\n"), 15,
                 "pressure = 1.0\ncycle = \"alternating\"\ncycle_amplitude = 0.1\ncycle_viscous_number = 1e3\n");
  const Model cyc = test::model_from(cycles);
  CHECK(cyc.params.get<paste::PasteParams>().dt_initial == doctest::Approx(1e-6));
}

TEST_CASE("paste: the same paste in another unit of length takes the same steps") {
  // The resistances grow as eta a and the pressure force on a disk as P a: a paste of disks
  // scaled by s moves at the same velocities, its times scaled by s (the viscous time eta a / P
  // of 2D). Scaled by a power of two, every operation is exact: the same bits. Before, 2D disks of
  // 1e-4 m failed at their first step (a first step of 1e-3 eta / P, twenty viscous times), and
  // scaled by 2^-8 their CG, which weighed the torques (of order a^2) against the forces (of order
  // a), took another count of iterations at the first step and parted at the fourth. (The dry
  // compressions stop at Phi = 0.8: 11,600 steps, not the 101,300 that make them static.)
  const double s = std::ldexp(1.0, -8);
  std::vector<State> end;
  for (double length : {1.0, s}) {
    const Model m = test::model_from(test::paste_disks(
        {.n = 80, .L = 10, .h_min = 1e-3, .dilation = 1.05, .phi = 0.8, .seed = 11, .length = length}));
    Simulation sim(m, 1);
    sim.restore(prepare_packing(m, 1, nullptr, nullptr));
    for (int k = 0; k < 15; ++k) REQUIRE(sim.step());
    end.push_back(sim.state());
  }
  CHECK(end[1].t == end[0].t * s);
  CHECK(end[1].particle_v == end[0].particle_v);
  for (size_t k = 0; k < end[0].particle_x.size(); ++k) CHECK(end[1].particle_x[k] == end[0].particle_x[k] * s);
  for (size_t k = 0; k < end[0].particle_w.size(); ++k) CHECK(end[1].particle_w[k] == end[0].particle_w[k] / s);
  // In SI units: disks of radius 35 to 50 um in water (eta = 1e-3 Pa s) under 100 N/m.
  std::string si = test::paste_disks(
      {.n = 80, .L = 10, .h_min = 1e-3, .viscosity = 1e-3, .dilation = 1.05, .phi = 0.8, .seed = 11, .length = 1e-4});
  si.replace(si.find("pressure = 1.0"), 14, "pressure = 100.0");
  si.replace(si.find("k_n = 1e4"), 9, "k_n = 1e6");  // kappa = k_n / P = 1e4, as above
  const Model m = test::model_from(si);
  Simulation sim(m, 1);
  sim.restore(prepare_packing(m, 1, nullptr, nullptr));
  const double phi0 = measure(m, sim.state()).phi;
  for (int k = 0; k < 15; ++k) REQUIRE(sim.step());
  CHECK(measure(m, sim.state()).phi > phi0);
}

TEST_CASE("paste: a packing at rest keeps a step of its time scale, run past equilibrium") {
  // At rest the net forces decay toward round-off, and each step's decay read as a change of the
  // right-hand side of order one: the step shrank without end (paste_iso with implicit contacts,
  // 600 eta/P past static, took 900,000 steps down to 4e-4 eta/P). Changes below the net force the
  // equilibrium criterion resolves (run.static_force_tol) no longer shrink it; the packing stays at
  // rest.
  const Model m = test::model_from(test::paste_disks(
      {.n = 80, .L = 10, .h_min = 1e-3, .dilation = 1.05, .seed = 11, .lubrication = "contacts = \"implicit\"\n"}));
  Simulation sim(m, 1);
  sim.restore(prepare_packing(m, 1, nullptr, nullptr));
  RunOptions to_rest;
  to_rest.steps = 20000;
  to_rest.stop_when_static = true;
  REQUIRE(sim.run(to_rest).end == RunEnd::kStatic);
  const double phi = measure(m, sim.state()).phi, t0 = sim.state().t;
  RunOptions past;
  past.steps = 20000;
  past.time = 600;
  const RunReport rep = sim.run(past);
  REQUIRE(rep.end == RunEnd::kDone);
  CHECK(sim.state().t >= t0 + 600);
  CHECK(rep.steps_done < 1000);
  CHECK(sim.is_static());
  CHECK(measure(m, sim.state()).phi == doctest::Approx(phi).epsilon(1e-8));
}
