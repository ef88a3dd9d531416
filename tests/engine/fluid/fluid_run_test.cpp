// The fluid in a run: divergence after projection, determinism across threads, bitwise restart,
// live steering of the viscosity and of a lid, and the failures it reports.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "core/machine.hpp"
#include "core/simd_level.hpp"
#include "fluid/module.hpp"
#include "fluid/step.hpp"
#include "silt/io.hpp"
#include "silt/text.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::fluid;

namespace {

// The lid-driven cavity at Re = 100 (side 1, lid speed 1).
std::string cavity(int dim, int n, const std::string& extra = "") {
  const bool d3 = dim == 3;
  const std::string c = std::to_string(n);
  return std::string("[scene]\ndimension = ") + (d3 ? "3" : "2") +
         "\n[domain]\nlo = " + (d3 ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]") +
         "\nhi = " + (d3 ? "[1.0, 1.0, 1.0]" : "[1.0, 1.0]") + "\n[fluid]\ncells = [" + c + ", " + c +
         (d3 ? ", " + c : "") + "]\nreynolds = 100.0\n" + extra +
         "\n[fluid.boundary]\ny_hi_velocity = " + (d3 ? "[1.0, 0.0, 0.0]" : "[1.0, 0.0]") + "\n";
}

double div_max(const Simulation& sim) { return sim.state().module_field(fluid_fields().stat)[kDivMax]; }

}  // namespace

TEST_CASE("fluid: the divergence after projection is at round-off with transforms, at the tolerance with CG") {
  auto fft = test::simulation_from(cavity(2, 32));
  for (int k = 0; k < 5; ++k) REQUIRE(fft->step());
  // |div u| h / U: round-off of the velocities (1) divided by h.
  CHECK(div_max(*fft) * (1.0 / 32) < 1e-13);
  CHECK(max_divergence(fft->model().params.get<FluidParams>(), fft->state()) == doctest::Approx(div_max(*fft)));
  double d[2];
  for (int k = 0; k < 2; ++k) {
    auto cg = test::simulation_from(
        cavity(2, 32, std::string("projection = \"multigrid_cg\"\ntolerance = ") + (k == 0 ? "1e-6" : "1e-11")));
    for (int s = 0; s < 5; ++s) REQUIRE(cg->step());
    d[k] = div_max(*cg);
    CHECK(cg->state().module_field(fluid_fields().stat)[kIters] > 0);
  }
  INFO("CG divergence at 1e-6 and 1e-11: " << d[0] << " " << d[1]);
  CHECK(d[0] < 1e-3);
  CHECK(d[1] < 1e-3 * d[0]);
}

TEST_CASE("fluid: the same bits on 1, 2 and 4 threads") {
  for (const std::string& scene : {cavity(2, 48), cavity(3, 12), cavity(2, 32, "projection = \"multigrid_cg\"")}) {
    uint64_t h[3];
    int k = 0;
    for (int threads : {1, 2, 4}) {
      auto sim = test::simulation_from(scene, threads);
      for (int s = 0; s < 8; ++s) REQUIRE(sim->step());
      h[k++] = state_hash(sim->state());
    }
    CHECK(h[0] == h[1]);
    CHECK(h[0] == h[2]);
  }
}

TEST_CASE("fluid: the AVX-512, AVX2 and baseline stencils give the same bits") {
  MESSAGE("widest vector instructions of this processor: " << simd_name(simd_level()));
  // Walls and a lid (each component updated on its own faces), periodic axes, an inflow and an
  // outflow (a row whose components start and end at different faces), Crank-Nicolson.
  const std::string open_channel =
      "[scene]\ndimension = 3\n[domain]\nlo = [0.0, 0.0, 0.0]\nhi = [2.0, 1.0, 1.0]\n"
      "periodic = [false, false, true]\n[fluid]\ncells = [20, 10, 10]\nreynolds = 50.0\n"
      "[fluid.boundary]\nx_lo = \"inflow\"\nx_lo_velocity = [1.0, 0.0, 0.0]\nx_lo_profile = \"parabolic\"\n"
      "x_hi = \"outflow\"\n";
  for (const std::string& scene : {cavity(3, 10), cavity(2, 24, "viscous = \"crank_nicolson\""), open_channel}) {
    CAPTURE(scene);
    uint64_t h[3];
    for (SimdLevel level : {SimdLevel::kAvx512, SimdLevel::kAvx2, SimdLevel::kBaseline}) {
      limit_simd(level);
      auto sim = test::simulation_from(scene);
      for (int s = 0; s < 6; ++s) REQUIRE(sim->step());
      limit_simd(SimdLevel::kAvx512);
      h[static_cast<int>(level)] = state_hash(sim->state());
    }
    CHECK(h[2] == h[0]);
    CHECK(h[1] == h[0]);
  }
}

TEST_CASE("fluid: a restart from a checkpoint continues bitwise") {
  for (const std::string& scene : {cavity(2, 24), cavity(2, 24, "projection = \"multigrid_cg\"")}) {
    const std::string path =
        (std::filesystem::temp_directory_path() / ("silt_fluid_restart_" + std::to_string(scene.size()) + ".ckpt"))
            .string();
    auto a = test::simulation_from(scene);
    for (int s = 0; s < 6; ++s) REQUIRE(a->step());
    write_checkpoint(path, a->model(), a->state());
    for (int s = 0; s < 6; ++s) REQUIRE(a->step());
    auto b = test::simulation_from(scene);
    b->restore(read_checkpoint(path, b->model()));
    for (int s = 0; s < 6; ++s) REQUIRE(b->step());
    CHECK(state_hash(b->state()) == state_hash(a->state()));
    std::filesystem::remove(path);
  }
}

TEST_CASE("fluid: a checkpoint of another grid is refused naming the cells, not as corrupt") {
  const std::string path = (std::filesystem::temp_directory_path() / "silt_fluid_other_grid.ckpt").string();
  auto a = test::simulation_from(cavity(2, 8));
  REQUIRE(a->step());
  write_checkpoint(path, a->model(), a->state());
  auto b = test::simulation_from(cavity(2, 16));
  CHECK_THROWS_WITH_AS(read_checkpoint(path, b->model()),
                       doctest::Contains("does not fit this scene (fluid_u has 72 entries where 272 are expected"),
                       IoError);
  CHECK_THROWS_WITH_AS(
      read_checkpoint(path, b->model()),
      doctest::Contains("the scene differs from it in fluid.cells = [8, 8] in the checkpoint, [16, 16] "
                        "in the scene"),
      IoError);
  // As many cells on a domain of another size: the velocities would be read on another spacing
  // (taken with a warning, a cavity's ke four times as large).
  std::string wide = cavity(2, 8);
  wide.replace(wide.find("hi = [1.0, 1.0]"), 15, "hi = [2.0, 2.0]");
  auto c = test::simulation_from(wide);
  CHECK_THROWS_WITH_AS(read_checkpoint(path, c->model()),
                       doctest::Contains("holds a fluid on another domain: domain.hi = [1, 1] in the checkpoint, "
                                         "[2, 2] in the scene"),
                       IoError);
  std::filesystem::remove(path);
}

TEST_CASE("fluid: a checkpoint whose velocity or pressure is not finite is refused naming the entry") {
  const std::string path = (std::filesystem::temp_directory_path() / "silt_fluid_not_finite.ckpt").string();
  auto a = test::simulation_from(cavity(2, 8));
  for (int s = 0; s < 3; ++s) REQUIRE(a->step());
  write_checkpoint(path, a->model(), a->state());
  CHECK_NOTHROW(read_checkpoint(path, a->model()));
  const auto refused = [&](const std::string& field) {
    State st = a->state();
    st.module_field(field == "p" ? fluid_fields().p : fluid_fields().u[1])[20] = std::nan("");
    write_checkpoint(path, a->model(), st);
    const std::string why = "is corrupt: fluid_" + field + "[20] is not finite";
    CHECK_THROWS_WITH_AS(read_checkpoint(path, a->model()), doctest::Contains(why.c_str()), IoError);
  };
  refused("p");
  refused("v");
  std::filesystem::remove(path);
}

TEST_CASE("fluid: steering the viscosity mid-run changes the decay rate from then on") {
  // Taylor-Green: the energy decays as exp(-4 nu k^2 t); nu 0.01 for t in [0, 0.3], then 0.03.
  const std::string scene =
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\nperiodic = [true, true]\n"
      "[fluid]\ncells = [32, 32]\nviscosity = 0.01\ninitial = \"taylor_green\"\ndt = 0.002\n";
  auto sim = test::simulation_from(scene);
  sim->prepare();  // the initial velocity
  const double e0 = kinetic_energy(sim->model().params.get<FluidParams>(), sim->state());
  while (sim->state().t < 0.3 - 1e-12) REQUIRE(sim->step());
  REQUIRE(steer(sim->model_for_steering(), parse_override("fluid.viscosity=0.03")) == "");
  const FluidParams& p = sim->model().params.get<FluidParams>();  // the steered model's
  CHECK(p.viscosity == 0.03);
  while (sim->state().t < 0.6 - 1e-12) REQUIRE(sim->step());
  const double k2 = 4 * std::numbers::pi * std::numbers::pi;
  const double expected = std::exp(-4 * k2 * (0.01 * 0.3 + 0.03 * 0.3));
  CHECK(kinetic_energy(p, sim->state()) / e0 == doctest::Approx(expected).epsilon(0.01));
  // A lid's speed too; the grid is not steerable.
  auto cav = test::simulation_from(cavity(2, 16));
  CHECK(steer(cav->model_for_steering(), parse_override("fluid.boundary.y_hi_velocity=[2.0, 0.0]")) == "");
  CHECK(cav->model().params.get<FluidParams>().grid.bc[1][1].velocity[0] == 2.0);
  CHECK(steer(cav->model_for_steering(), parse_override("fluid.cells=[8, 8]")) != "");
}

TEST_CASE(
    "fluid: the initial vortex's rate is its first state's and a note past the limit, a bulk velocity's bound "
    "refuses") {
  // The Taylor-Green vortex on odd and even grids, a box with Lx != Ly, in 2D and 3D: its largest
  // face values are the products of each axis's largest factor, exactly the first state's rate.
  // (cells of 1/16 along every axis)
  // (no structured bindings: clang's CAPTURE cannot take one)
  for (const auto& grid : {std::pair{"[16, 16]", "[1.0, 1.0]"}, std::pair{"[15, 17]", "[0.9375, 1.0625]"},
                           std::pair{"[16, 12, 9]", "[1.0, 0.75, 0.5625]"}}) {
    const std::string cells = grid.first, hi = grid.second;
    CAPTURE(cells);
    const bool d3 = cells.size() > 8;
    const std::string scene = std::string("[scene]\ndimension = ") + (d3 ? "3" : "2") +
                              "\n[domain]\nlo = " + (d3 ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]") + "\nhi = " + hi +
                              "\nperiodic = " + (d3 ? "[true, true, true]" : "[true, true]") +
                              "\n[fluid]\ncells = " + cells +
                              "\nviscosity = 0.01\ninitial = \"taylor_green\"\ninitial_velocity = 3.0\n";
    auto sim = test::simulation_from(scene);
    sim->prepare();  // the initial velocity
    const FluidParams& p = sim->model().params.get<FluidParams>();
    const double rate = cfl_number(p, sim->state(), 1.0);
    CHECK(rate > 0);
    CHECK(vortex_rate(p) == doctest::Approx(rate).epsilon(1e-14));
    CHECK(known_rate(p) == 0);  // (periodic: no wall, no drive)
    // A fixed step past the limit by it is a note, not a refusal: a state restored or kept through
    // a change is not the vortex (a decayed one, restored, was refused a step 13,000 times its limit).
    const double dt = 2.0 / vortex_rate(p);
    const Model m = test::model_from(scene + "dt = " + std::to_string(dt) + "\n");
    const std::string text = describe(m);
    INFO(text);
    const std::string label = "the initial vortex (fluid.initial_velocity) alone gives a CFL number dt sum |U|/h = ";
    const size_t at = text.find(label);
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(text.substr(at + label.size())) == doctest::Approx(2).epsilon(1e-4));  // (dt with 6 decimals)
    CHECK(text.find("above 1.6 at this fixed step: a run from it fails at its first step") != std::string::npos);
  }
  // The note at a run's start is of the step it takes: a fixed step steered after a first
  // preparation gave the old step's note, and the new one beside it.
  {
    const std::string scene =
        "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\n"
        "periodic = [true, true]\n[fluid]\ncells = [16, 16]\nviscosity = 0.1\n"
        "initial = \"taylor_green\"\ninitial_velocity = 3.0\ndt = 0.001\n";
    auto sim = test::simulation_from(scene);
    sim->prepare();
    CHECK(sim->take_notices().empty());
    const double past = 2.0 / vortex_rate(sim->model().params.get<FluidParams>());
    REQUIRE(steer(sim->model_for_steering(), parse_override("fluid.dt=" + format_number(past, 17))) == "");
    sim->prepare();
    sim->prepare();  // (prepared twice: one note)
    const std::vector<std::string> notes = sim->take_notices();
    REQUIRE(notes.size() == 1);
    INFO(notes[0]);
    CHECK(notes[0].find("dt sum |U|/h = 2 above 1.6") != std::string::npos);
    // An adaptive step's too: a target CFL number steered at step 0 (the note read the state's step).
    REQUIRE(steer(sim->model_for_steering(), parse_override("fluid.cfl=1e-7")) == "");
    sim->prepare();
    const std::vector<std::string> adaptive = sim->take_notices();
    REQUIRE(adaptive.size() == 1);
    CHECK(adaptive[0].find("fluid steps of") != std::string::npos);
  }
  // A bulk velocity: the mean of u over the faces after the first step, so at least it somewhere.
  const std::string channel =
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [2.0, 1.0]\nperiodic = [true, false]\n"
      "[fluid]\ncells = [32, 16]\nviscosity = 0.1\nbulk_velocity = 10.0\n";
  CHECK(test::scene_error(channel + "dt = 0.02\n")
            .find("the bulk velocity (fluid.bulk_velocity) alone gives a CFL number dt sum |U|/h = 3.2 above 1.6") !=
        std::string::npos);
  CHECK(test::scene_error(channel + "dt = 0.01\n").empty());  // 1.6 itself: the flow decides
}

TEST_CASE("fluid: a step beyond the CFL limit stops the run naming fluid.dt, the lid's speed counted") {
  // The fluid starts at rest, but the lid moves at once: a CFL number of 6.4 at the lid. The rate
  // of a state at rest was 0 and its first step ran, reported as CFL 0 and kept as the last good
  // state; so did the step after a lid steered twenty times faster.
  // Such a fixed step is refused with the scene now; the lid's 1.44 at this one, the flow it drives
  // passes 1.6 at the second step.
  CHECK(test::scene_error(cavity(2, 32, "dt = 0.2")).find("CFL number dt sum |U|/h = 6.4 above 1.6") !=
        std::string::npos);
  auto sim = test::simulation_from(cavity(2, 32, "dt = 0.045"));
  REQUIRE(sim->step());
  CHECK_FALSE(sim->step());
  CHECK(sim->state().failure.step == 2);
  CHECK(sim->state().failure.parameter == "fluid.dt");
  CHECK(sim->state().failure.message.find("CFL") != std::string::npos);
  auto slow = test::simulation_from(cavity(2, 16, "dt = 0.01\nvelocity_scale = 1.0"));
  REQUIRE(slow->step());
  CHECK(test::observe(slow->model(), slow->state(), "fluid.cfl") == doctest::Approx(0.16));
  // A lid steered twenty times faster under the fixed step: refused at once (the step failed).
  CHECK(steer(slow->model_for_steering(), parse_override("fluid.boundary.y_hi_velocity=[20.0, 0.0]"))
            .find("CFL number dt sum |U|/h = 3.2 above 1.6") != std::string::npos);
  REQUIRE(slow->step());
  // An adaptive first step with a velocity scale below the lid's speed: held to the lid's.
  auto scaled = test::simulation_from(cavity(2, 16, "velocity_scale = 0.1"));
  CHECK(scaled->model().params.get<FluidParams>().dt <= 0.5 / 16 * (1 + 1e-12));
  REQUIRE(scaled->step());
  CHECK(test::observe(scaled->model(), scaled->state(), "fluid.cfl") <= 0.5 + 1e-12);
}

TEST_CASE("fluid: after a failed step, the state restored steps as it would have") {
  // The failed step's NaN stayed in the workspace's arrays (the last substep's advection, which
  // the first substep multiplies by 0): a good checkpoint restored failed again at once, in the
  // shell until the scene was loaded again.
  const std::string channel =
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [2.0, 1.0]\nperiodic = [true, false]\n"
      "[fluid]\ncells = [16, 8]\nviscosity = 0.1\npressure_gradient = 1.2\ndt = 0.01\n";
  auto sim = test::simulation_from(channel);
  // (The imposed gradient is the observable's from the start: it read 0 until a step stored it.)
  CHECK(test::observe(sim->model(), sim->state(), "fluid.pressure_gradient") == 1.2);
  for (int k = 0; k < 10; ++k) REQUIRE(sim->step());
  const State good = sim->state();
  auto straight = test::simulation_from(channel);
  for (int k = 0; k < 15; ++k) REQUIRE(straight->step());
  REQUIRE(steer(sim->model_for_steering(), parse_override("fluid.pressure_gradient=1e300")) == "");
  bool failed = false;
  for (int k = 0; k < 5 && !failed; ++k) failed = !sim->step();
  REQUIRE(failed);
  REQUIRE(steer(sim->model_for_steering(), parse_override("fluid.pressure_gradient=1.2")) == "");
  sim->restore(good);
  for (int k = 0; k < 5; ++k) REQUIRE(sim->step());
  CHECK(state_hash(sim->state()) == state_hash(straight->state()));
}

TEST_CASE("fluid: scene errors are located at their key") {
  std::string uneven = cavity(2, 16);
  uneven.replace(uneven.find("[16, 16]"), 8, "[16, 8]");
  const std::string err = test::scene_error(uneven);
  INFO(err);
  CHECK(err.find("bad.toml:7:9") != std::string::npos);  // the fluid.cells value
  CHECK(err.find("spacing") != std::string::npos);
  // ... and says what would do: the cells where they fit the domain, else the domain's lengths and
  // the nearest cells along x that fit (it named the two spacings only).
  CHECK(err.find("give fluid.cells = [16, 16]") != std::string::npos);
  std::string long_box = cavity(2, 16);
  long_box.replace(long_box.find("hi = [1.0, 1.0]"), 15, "hi = [1.9, 1.0]");
  const std::string off = test::scene_error(long_box);
  INFO(off);
  CHECK(off.find("make it 0.95 m along y (8 cells), or give other cells along x (fluid.cells = [19, 10])") !=
        std::string::npos);
  const std::string inflow_only =
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [1.0, 1.0]\n[fluid]\ncells = [8, 8]\n"
      "viscosity = 0.1\n[fluid.boundary]\nx_lo = \"no_slip\"\ny_lo = \"inflow\"\ny_lo_velocity = [0.0, 1.0]\n";
  const std::string no_outflow = test::scene_error(inflow_only);
  INFO(no_outflow);
  CHECK(no_outflow.find("outflow") != std::string::npos);
  CHECK(no_outflow.find("bad.toml:11:") != std::string::npos);  // at the inflow face (it was x_lo's line)
  // Gravity on a fluid alone was accepted, listed by `silt check`, and did nothing.
  const std::string gravity = test::scene_error(cavity(2, 8) + "[gravity]\nvector = [0.0, -9.81]\n");
  INFO(gravity);
  CHECK(gravity.find("bad.toml:13:") != std::string::npos);
  CHECK(gravity.find("pressure_gradient") != std::string::npos);
  // A fixed step and the adaptive step's keys are alternatives: fluid.dt given over a scene's
  // fluid.cfl replaces it, both in a file are refused (fluid.cfl and fluid.dt_max beside fluid.dt
  // were accepted and did nothing).
  const Model fixed = compile(parse_scene(cavity(2, 8, "cfl = 0.3"), "cavity.toml", {parse_override("fluid.dt=0.01")}));
  CHECK(fixed.params.get<FluidParams>().dt_fixed);
  CHECK_FALSE(fixed.adaptive_dt);
  for (const std::string both : {"dt = 0.01\ncfl = 0.3", "dt = 0.01\ndt_max = 0.5"}) {
    CAPTURE(both);
    CHECK(test::scene_error(cavity(2, 8, both)).find("not both") != std::string::npos);
  }
  // A line probe without a name (the summary's key "") or of one point, from = to (its s, a
  // fraction of its length, is then 0 / 0): accepted, both.
  const std::string probe = "[[output.lines]]\nname = \"NAME\"\nfield = \"u\"\nfrom = [0.5, 0.1]\nto = [0.5, 0.9]\n";
  auto probed = [&](const std::string& from, const std::string& to) {
    std::string text = cavity(2, 8) + probe;
    text.replace(text.find(from), from.size(), to);
    return test::scene_error(text);
  };
  CHECK(probed("\"NAME\"", "\"\"").find("a line probe needs a name") != std::string::npos);
  CHECK(probed("[0.5, 0.9]", "[0.5, 0.1]").find("the probe's ends are the same point") != std::string::npos);
  CHECK(probed("NAME", "u_centreline") == "");
  // A million points in all at most (a hundred probes of a million each passed, and the summary
  // written after the run took 4.7 GB per ten of them); their summary's memory is in the estimate.
  const std::string many = cavity(2, 8) + probe + "points = 600000\n" + probe + "points = 400001\n";
  CHECK(
      test::scene_error(many).ends_with("the line probes sample 1000001 points in all, above 1000000 (a summary "
                                        "of about 140 MB): use fewer; the grid has 8 cells along its longest axis"));
  std::string fewer = many;
  fewer.replace(fewer.find("400001"), 6, "400000");
  fewer.replace(fewer.rfind("NAME"), 4, "other");
  const Model probed_model = test::model_from(fewer);
  CHECK(estimated_memory_bytes(probed_model) - estimated_memory_bytes(test::model_from(cavity(2, 8))) ==
        doctest::Approx(1e6 * 420));  // (520 in 3D)
  const std::string big = test::scene_error(cavity(3, 4000));
  INFO(big);
  CHECK(big.find("GiB") != std::string::npos);
  // With the cells that would fit, alike along every axis (it said "use fewer cells").
  const auto at = big.find("use fewer cells (at most about [");
  REQUIRE(at != std::string::npos);
  const double n = std::stod(big.substr(at + 32));
  CHECK(n > 100);
  CHECK(estimated_memory_bytes(test::model_from(cavity(3, static_cast<int>(n)))) < available_memory_bytes());
  // Grains in a fluid scene: refused at [fluid] (the step graph found two stages writing dt and
  // reported an internal error, after `silt check` had printed the scene).
  const std::string grains = test::scene_error(cavity(2, 8) +
                                               "[contact]\nmodel = \"spring_dashpot\"\nrestitution = 0.9\n"
                                               "contact_time = 1e-3\n[[grains]]\nradius = 0.1\ndensity = 1.0\n"
                                               "placement = \"explicit\"\npositions = [[0.5, 0.5]]\n");
  INFO(grains);
  CHECK(grains.find("bad.toml:7:9") != std::string::npos);
  CHECK(grains.find("not coupled yet") != std::string::npos);
  // A table of a module that acts on grains, in a fluid scene: refused at it (an empty [shear],
  // [box], [prepare], [drag] or [lubrication] turned its module on and the step graph reported an
  // internal error, after `silt check` had printed the scene). The cavity's text ends at line 11.
  // (no structured bindings: clang's CAPTURE cannot take one)
  for (const auto& c : std::vector<std::pair<std::string, std::string>>{
           {"[shear]\n", "bad.toml:12:1"},
           {"[box]\npressure = 1.0\n", "bad.toml:13:12"},
           {"[prepare]\n", "bad.toml:12:1"},
           {"[drag]\nviscosity = 1.0\n", "bad.toml:13:13"},
           {"[lubrication]\nviscosity = 1.0\ndt = 0.1\n", "bad.toml:14:6"}}) {
    const std::string& table = c.first;
    CAPTURE(table);
    const std::string e = test::scene_error(cavity(2, 8) + table);
    CHECK(e.rfind(c.second, 0) == 0);
    CHECK(e.find(table.substr(0, table.find(']') + 1) + " acts on grains, and this scene has none") !=
          std::string::npos);
  }
  // A [fluid] without its cells is a fluid missing them (it was taken for grains missing a
  // contact law).
  std::string no_cells = cavity(2, 8);
  no_cells.erase(no_cells.find("cells = [8, 8]\n"), 15);
  CHECK(test::scene_error(no_cells).find("missing required key 'fluid.cells'") != std::string::npos);
  // The viscosity and the Reynolds number are alternatives: one given replaces the other (a
  // viscosity set over the cavity's Re was refused as "not used"), both in a file are refused.
  const Model viscous = compile(parse_scene(cavity(2, 8), "cavity.toml", {parse_override("fluid.viscosity=0.05")}));
  CHECK(viscous.params.get<FluidParams>().viscosity == 0.05);
  CHECK(test::scene_error(cavity(2, 8, "viscosity = 0.05")).find("fluid.viscosity") != std::string::npos);
  // Keys that do nothing in this scene are refused, not accepted and ignored.
  for (const std::string ignored :
       {"tolerance = 1e-6", "max_iterations = 50", "initial_velocity = 2.0", "drive_axis = \"y\""}) {
    CAPTURE(ignored);
    const std::string key = "fluid." + ignored.substr(0, ignored.find(' '));
    CHECK(test::scene_error(cavity(2, 8, ignored)).find("'" + key + "' is set but not used") != std::string::npos);
  }
  CHECK(test::scene_error(cavity(2, 8) + "x_lo_profile = \"parabolic\"\n")  // the last table: [fluid.boundary]
            .find("'fluid.boundary.x_lo_profile' is set but not used") != std::string::npos);
  CHECK(test::scene_error(cavity(2, 8) + "[run]\ndt = 0.001\n").find("run.dt does not apply") != std::string::npos);
  // One drive: both in a scene is an error; a flow rate set over a pressure-driven scene drives it
  // (before, the pressure gradient kept driving and the bulk velocity only set the velocity scale).
  const std::string channel =
      "[scene]\ndimension = 2\n[domain]\nlo = [0.0, 0.0]\nhi = [2.0, 1.0]\nperiodic = [true, false]\n"
      "[fluid]\ncells = [8, 4]\nviscosity = 0.1\npressure_gradient = 1.0\n";
  CHECK(test::scene_error(channel + "bulk_velocity = 1.0\n").find("not both") != std::string::npos);
  const Model m = compile(parse_scene(channel, "channel.toml", {parse_override("fluid.bulk_velocity=2.0")}));
  const FluidParams& p = m.params.get<FluidParams>();
  CHECK(p.drive == Drive::kFlowRate);
  CHECK(p.bulk_velocity == 2.0);
}

TEST_CASE("fluid: the memory estimate covers what a run holds, and not much more") {
  // The estimate was 30 to 45 % under a run's resident memory (it left out the restart
  // point's copy of the state, the transforms' buffers and a sample's copies): a grid it let
  // through could end in an allocation failure.
  for (const std::string& scene : {cavity(3, 48), cavity(2, 256), cavity(3, 32, "projection = \"multigrid_cg\""),
                                   cavity(3, 32, "viscous = \"explicit\"\ndt = 0.001")}) {
    auto sim = test::simulation_from(scene, 2);
    for (int k = 0; k < 3; ++k) REQUIRE(sim->step());
    const FluidParams& p = sim->model().params.get<FluidParams>();
    // What is held between steps, and the transient copies of a sample (padded velocity and
    // pressure, the vorticity at the cells).
    const double sample = 8.0 * (static_cast<double>(Layout(p.grid).size) * (p.grid.dim + 1) +
                                 static_cast<double>(p.grid.cells()) * (p.grid.dim == 3 ? 3 : 1));
    const double need = static_cast<double>(sim->memory_bytes()) + sample;
    const double estimate = estimated_memory_bytes(sim->model());
    INFO("estimate " << estimate / 1e6 << " MB, held and a sample " << need / 1e6 << " MB");
    CHECK(estimate >= need);
    CHECK(estimate < 1.5 * need);
  }
}
