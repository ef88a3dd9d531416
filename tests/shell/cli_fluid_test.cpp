// The fluid through the command line: the shipped cavity with its probes, frames and VTK files,
// a failure's exit code and message, and the shell steering the Reynolds number.
#include <doctest/doctest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "shell/cli_fixtures.hpp"

using namespace silt::test;

TEST_CASE("silt run: the cavity's summary holds its probes, frames draw vorticity, VTK writes the fields") {
  const std::string dir = "cli_fluid_out";
  std::filesystem::remove_all(dir);
  std::filesystem::remove_all(dir + "_vtk");
  std::filesystem::remove_all(dir + "_frames");
  const Result r =
      silt_cli("run " + scene_path("cavity_2d") + " --set fluid.cells=[32,32] --set run.time=2 --summary " + dir +
               ".json --frames " + dir + "_frames --frame-every 200 --vtk " + dir + "_vtk --quiet");
  REQUIRE(r.code == 0);
  CHECK(r.out.find("cell-steps/s") != std::string::npos);
  const auto j = nlohmann::json::parse(read_file(dir + ".json"));
  CHECK(j["cells"] == 1024);
  CHECK(j["fluid_cell_steps_per_s"].get<double>() > 0);
  const auto& u = j["lines"]["u_centreline"];
  REQUIRE(u["value"].size() == 129);
  CHECK(u["value"][0].get<double>() == doctest::Approx(0).epsilon(1e-12));  // the bottom wall
  CHECK(u["value"][128].get<double>() == doctest::Approx(1.0));             // the lid
  CHECK(u["value"][64].get<double>() < 0);                                  // the return flow
  CHECK(j["lines"]["v_centreline"]["x"][0].size() == 2);
  CHECK(j["solver"]["solves"].get<double>() > 0);
  // Counts as integers (INTERFACE.md's N), as the number of cells.
  CHECK(j["cells"].is_number_integer());
  CHECK(j["solver"]["solves"].is_number_integer());
  CHECK(j["solver"]["iters_max"].is_number_integer());
  CHECK(j["solver"]["iters_mean"].is_number_float());  // a mean, whole or not
  CHECK(std::filesystem::exists(dir + "_frames/frame_000000.png"));
  CHECK(std::filesystem::exists(dir + "_vtk/fields_000000.vti"));
  CHECK(read_file(dir + "_vtk/fields_000000.vti").find("Name=\"vorticity\"") != std::string::npos);
  // No grains: no grains or contacts files (two empty ones a sample before), the fields part 0.
  CHECK_FALSE(std::filesystem::exists(dir + "_vtk/grains_000000.vtu"));
  CHECK_FALSE(std::filesystem::exists(dir + "_vtk/contacts_000000.vtp"));
  CHECK(read_file(dir + "_vtk/index.pvd").find("part=\"0\" file=\"fields_000000.vti\"") != std::string::npos);
}

TEST_CASE("silt run: a fluid step past the CFL limit exits 3 naming fluid.dt, or 2 where the lid alone passes it") {
  // The lid at 1 m/s gives 1.44 at this step; the flow it drives passes 1.6 at the second step.
  const Result r = silt_cli("run " + scene_path("cavity_2d") +
                            " --set fluid.cells=[32,32] --set fluid.dt=0.045 --set run.time=5 --quiet");
  CHECK(r.code == 3);
  CHECK(r.out.find("fluid.dt") != std::string::npos);
  CHECK(r.out.find("CFL") != std::string::npos);
  // Where (the contract's "the particle or cell"): the fastest face of the flow, below the lid.
  CHECK(r.out.find("(fastest at cell (17, 31), x = (0.5312, 0.9844) m: u = ") != std::string::npos);
  // The lid alone gives 6.4, in units of L / U = 1 s: refused at the key (`silt check` said ok).
  const Result lid = silt_cli("check " + scene_path("cavity_2d") + " --set fluid.cells=[32,32] --set fluid.dt=0.2");
  CHECK(lid.code == 2);
  CHECK(lid.out.find("the walls' and inflows' speeds alone give a CFL number dt sum |U|/h = 6.4 above 1.6") !=
        std::string::npos);
  CHECK(lid.out.find("reduce fluid.dt below 0.04999 L/U") != std::string::npos);  // strictly below 0.05
}

TEST_CASE("silt check: a fluid scene's cells, bytes per cell and dimensionless groups, a grid too large is refused") {
  const Result ok = silt_cli("check " + scene_path("cavity_2d"));
  CHECK(ok.code == 0);
  CHECK(ok.out.find("128 x 128 cells") != std::string::npos);
  CHECK(ok.out.find("bytes per cell") != std::string::npos);
  CHECK(ok.out.find("Re = U L / nu = 100") != std::string::npos);
  // A run in steps of an adaptive step: its time is not steps x the first step (it said 0.195 s).
  const Result steps = silt_cli("check " + scene_path("cavity_2d") + " --set run.steps=100");
  CHECK(steps.out.find("100 steps (adaptive time step: the first 0.0019531 s)") != std::string::npos);
  const Result big = silt_cli("check " + scene_path("cavity_3d") + " --set fluid.cells=[4000,4000,4000]");
  CHECK(big.code == 2);
  CHECK(big.out.find("GiB") != std::string::npos);
}

TEST_CASE("silt play: a fluid's initial field changed before the first step makes the state again") {
  // The state at t = 0 was kept whenever the grid was the same: the vortex stayed at U0 = 1 while
  // the model (its step, its viscosity from Re) took U0 = 2.
  const std::string script =
      write_file("cli_fluid_initial.silt", "load " + scene_path("taylor_green_2d") +
                                               "\nprint fluid.ke\nset fluid.initial_velocity 2\nprint fluid.ke\nrun 2\n"
                                               "set fluid.initial_velocity 0.5\n");
  const Result r = silt_cli("play " + script);
  CHECK(r.code == 0);
  CHECK(r.out.find("fluid.ke = 0.25 J") != std::string::npos);
  CHECK(r.out.find("the state at t = 0 made again") != std::string::npos);
  CHECK(r.out.find("fluid.ke = 1 J") != std::string::npos);
  CHECK(r.out.find("fluid.initial_velocity = 0.5 (state kept)") != std::string::npos);  // once stepped
  // (and it did nothing without a word)
  CHECK(r.out.find("note: fluid.initial_velocity makes the state at t = 0 only: the state kept (step 2) goes on as "
                   "it was; `reset` starts again with it") != std::string::npos);
}

TEST_CASE("silt run and check: a --set that replaces the scene's alternative key says so") {
  // The file's fluid.dt went under --set fluid.dt_max, and the cavity's reynolds under --set
  // fluid.viscosity, without a word (the shell's `set` says it, a file giving both is refused).
  const Result dt = silt_cli("run " + scene_path("channel") + " --set fluid.dt_max=0.001 --steps 2 --quiet");
  CHECK(dt.code == 0);
  CHECK(dt.out.find("silt: note: --set fluid.dt_max replaces the scene's fluid.dt, an alternative to it") !=
        std::string::npos);
  const Result nu = silt_cli("check " + scene_path("cavity_2d") + " --set fluid.viscosity=0.01");
  CHECK(nu.code == 0);
  CHECK(nu.out.find("silt: note: --set fluid.viscosity replaces the scene's fluid.reynolds") != std::string::npos);
  const Result same = silt_cli("check " + scene_path("cavity_2d") + " --set fluid.reynolds=400");
  CHECK(same.out.find("note:") == std::string::npos);
}

TEST_CASE(
    "silt run --restore: an initial value that differs from the checkpoint's says it does nothing past the start") {
  const std::string ckpt = "cli_fluid_initial_restore.ckpt";
  REQUIRE(silt_cli("run " + scene_path("taylor_green_2d") + " --steps 2 --quiet --save " + ckpt).code == 0);
  const Result r = silt_cli("run " + scene_path("taylor_green_2d") + " --restore " + ckpt +
                            " --set fluid.initial_velocity=2 --steps 1 --quiet");
  CHECK(r.code == 0);
  CHECK(r.out.find("fluid.initial_velocity = 1 in the checkpoint, 2 in the scene (it makes the state at t = 0 only: "
                   "this one, at step 2, goes on as it was)") != std::string::npos);
  std::filesystem::remove(ckpt);
}

TEST_CASE("silt play: the shell steers the cavity's Reynolds number while it runs") {
  const std::string script =
      write_file("cli_fluid_steer.silt", "load " + scene_path("cavity_2d") +
                                             "\nset fluid.cells [24, 24]\nrun until t >= 0.5\nset fluid.reynolds 400\n"
                                             "get fluid.viscosity\nrun until t >= 1\nprint t fluid.div_max\n");
  const Result r = silt_cli("play " + script);
  CHECK(r.code == 0);
  CHECK(r.out.find("0.0025") != std::string::npos);  // mu = rho U L / Re = 1 / 400
}

TEST_CASE("silt run: the cavity stops when steady, with the summary's status steady, or says it did not get there") {
  const std::string json = "cli_fluid_steady.json";
  const Result r = silt_cli("run " + scene_path("cavity_2d") +
                            " --set fluid.cells=[16,16] --set fluid.reynolds=10 --summary " + json + " --quiet");
  REQUIRE(r.code == 0);
  CHECK(r.out.find("status steady") != std::string::npos);
  const auto j = nlohmann::json::parse(read_file(json));
  CHECK(j["status"] == "steady");
  CHECK(j["warnings"].empty());
  CHECK(j["sim_time"].get<double>() < 50);  // the scene's run.time is the cap
  CHECK(j["observables"]["fluid.change_rate"]["last"].get<double>() < 1e-6);
  const Result short_run = silt_cli("run " + scene_path("cavity_2d") +
                                    " --set fluid.cells=[16,16] --time 0.5 --summary " + json + " --quiet");
  REQUIRE(short_run.code == 0);
  const auto k = nlohmann::json::parse(read_file(json));
  CHECK(k["status"] == "ok");
  CHECK(k["warnings"].dump().find("run.stop_when_steady") != std::string::npos);
  CHECK(silt_cli("check " + scene_path("cavity_2d")).out.find("or until steady") != std::string::npos);
}

TEST_CASE("silt play: run until steady, and a target CFL steered between runs") {
  const std::string script = write_file("cli_fluid_until_steady.silt",
                                        "load " + scene_path("cavity_2d") +
                                            "\nset fluid.cells [16, 16]\nset fluid.reynolds 10\nset fluid.cfl 0.25\n"
                                            "run 20\nprint fluid.cfl\nset fluid.cfl 0.4\nrun 1\nprint fluid.cfl\n"
                                            "run until steady\nprint fluid.change_rate\n");
  const Result r = silt_cli("play " + script);
  INFO(r.out);
  CHECK(r.code == 0);
  CHECK(r.out.find("fluid.cfl = 0.25") != std::string::npos);
  CHECK(r.out.find("fluid.cfl = 0.4") != std::string::npos);  // at the first step after the set
  CHECK(r.out.find("steady: ") != std::string::npos);
  const std::string no_fluid =
      write_file("cli_fluid_until_steady_dry.silt", "load " + scene_path("collision_normal") + "\nrun until steady\n");
  const Result dry = silt_cli("play " + no_fluid);
  CHECK(dry.code == 2);
  CHECK(dry.out.find("no [fluid]") != std::string::npos);
}

TEST_CASE("silt play: run until on a value of the last step is not tested before the first step") {
  // fluid.change_rate, fluid.cfl and fluid.div_max read 0 before any step: "run until
  // fluid.change_rate < 1e-3" held at step 0. After a step it is tested as any other.
  const std::string script =
      write_file("cli_fluid_until_last_step.silt",
                 "load " + scene_path("cavity_2d") +
                     "\nset fluid.cells [16, 16]\nrun until fluid.change_rate < 1e3\nprint step\n"
                     "run until fluid.change_rate < 1e3\nprint step\nreset\n"
                     "run until fluid.ke >= 0\nprint step\n"
                     "run until step >= 0 or fluid.cfl < 0.6\nprint step\n"
                     "run 3\nrun until step >= 0 or fluid.cfl < 0.6\nprint step\n");
  const Result r = silt_cli("play " + script);
  INFO(r.out);
  CHECK(r.code == 0);
  const size_t first = r.out.find("condition met: 10 steps");  // tested every 10 steps
  REQUIRE(first != std::string::npos);
  const size_t again = r.out.find("condition met: 0 steps in", first);  // after a step: at once
  REQUIRE(again != std::string::npos);
  CHECK(r.out.find("step 10\n", again) != std::string::npos);
  const size_t state = r.out.find("now t = 0 s, step 0\n", again);  // a value of the state: at once
  REQUIRE(state != std::string::npos);
  // The other terms of the condition are tested at step 0 as always (this one ran 10 steps).
  const size_t mixed = r.out.find("now t = 0 s, step 0\n", state + 1);
  REQUIRE(mixed != std::string::npos);
  // The state a run starts from is tested at any step (from step 3 this ran to step 10).
  CHECK(r.out.find("condition met: 0 steps in", mixed) != std::string::npos);
  CHECK(r.out.find("step 3\n", mixed) != std::string::npos);
  CHECK(r.out.find("step 10\n", mixed) == std::string::npos);
}

TEST_CASE("silt play: the shipped cavity_reynolds.silt plays, on a smaller grid and for less time") {
  // The script's own commands, with the grid, the frames' size and the times made small (its full
  // length is `silt play scenes/cavity_reynolds.silt`); each replaced line must be in it.
  std::string text = read_file(std::string(SILT_SOURCE_DIR) + "/scenes/cavity_reynolds.silt");
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    REQUIRE_MESSAGE(at != std::string::npos, "scenes/cavity_reynolds.silt no longer says: " << from);
    text.replace(at, from.size(), to);
  };
  replace("load cavity_2d.toml", "load " + scene_path("cavity_2d"));
  replace("set fluid.cells [96, 96]", "set fluid.cells [24, 24]");
  replace("set render.width 640", "set render.width 160");
  replace("set render.height 640", "set render.height 160");
  replace("every 400", "every 20");
  replace("frames cavity_film every 150", "frames cli_fluid_film every 30");
  replace("run until t >= 8", "run until t >= 0.4");
  replace("run until t >= 16", "run until t >= 0.8");
  replace("run until t >= 24", "run until t >= 1.2");
  replace("render cavity_final.png", "render cli_fluid_final.png");
  std::filesystem::remove_all("cli_fluid_film");
  const Result r = silt_cli("play " + write_file("cli_fluid_reynolds.silt", text));
  INFO(r.out);
  CHECK(r.code == 0);
  CHECK(r.out.find("mu = 0.01 Pa s") != std::string::npos);  // check, at load: Re = 100
  CHECK(std::filesystem::exists("cli_fluid_film/frame_000000.png"));
  CHECK(std::filesystem::exists("cli_fluid_final.png"));
}

TEST_CASE("silt run: a failed run samples its last good state once, in the stats and the summary's last values") {
  // Its stats had the rows of the steps sampled before (here only t = 0) and the summary's last
  // values were of that sample, while its steps, its time and its probes were the last good
  // state's.
  const std::string stem = "cli_fluid_failed";
  const Result r = silt_cli("run " + scene_path("channel") + " --set fluid.pressure_gradient=50 --stats " + stem +
                            ".csv --summary " + stem + ".json --quiet");
  REQUIRE(r.code == 3);
  const auto j = nlohmann::json::parse(read_file(stem + ".json"));
  REQUIRE(j["status"] == "failed");
  const int64_t steps = j["steps"].get<int64_t>();
  CHECK(steps > 0);
  CHECK(j["observables"]["step"]["last"].get<double>() == static_cast<double>(steps));
  CHECK(j["observables"]["t"]["last"].get<double>() == j["sim_time"].get<double>());
  CHECK(j["observables"]["fluid.ke"]["last"].get<double>() > 0);
  const std::string csv = read_file(stem + ".csv");
  CHECK(csv.find("\n" + std::to_string(steps) + ",") == std::string::npos);  // (t first, then step)
  CHECK(csv.find("," + std::to_string(steps) + ",") != std::string::npos);
}
