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
  CHECK(std::filesystem::exists(dir + "_frames/frame_000000.png"));
  CHECK(std::filesystem::exists(dir + "_vtk/fields_000000.vti"));
  CHECK(read_file(dir + "_vtk/fields_000000.vti").find("Name=\"vorticity\"") != std::string::npos);
}

TEST_CASE("silt run: a fluid step past the CFL limit exits 3 naming fluid.dt") {
  const Result r = silt_cli("run " + scene_path("cavity_2d") +
                            " --set fluid.cells=[32,32] --set fluid.dt=0.2 --set run.time=5 --quiet");
  CHECK(r.code == 3);
  CHECK(r.out.find("fluid.dt") != std::string::npos);
  CHECK(r.out.find("CFL") != std::string::npos);
}

TEST_CASE("silt check: a fluid scene's cells, bytes per cell and dimensionless groups, a grid too large is refused") {
  const Result ok = silt_cli("check " + scene_path("cavity_2d"));
  CHECK(ok.code == 0);
  CHECK(ok.out.find("128 x 128 cells") != std::string::npos);
  CHECK(ok.out.find("bytes per cell") != std::string::npos);
  CHECK(ok.out.find("Re = U L / nu = 100") != std::string::npos);
  const Result big = silt_cli("check " + scene_path("cavity_3d") + " --set fluid.cells=[4000,4000,4000]");
  CHECK(big.code == 2);
  CHECK(big.out.find("GiB") != std::string::npos);
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
