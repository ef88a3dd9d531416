// What a user types, pipes, schedules or crafts never crashes or hangs silt: each reproducer ends
// in a clear message and the exit code of the contract (INTERFACE.md).
#include <doctest/doctest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "shell/cli_fixtures.hpp"
#include "shell/shell_fixtures.hpp"
#include "silt/io.hpp"

using silt::test::contains;
using silt::test::Result;
using silt::test::scene_path;
using silt::test::silt_cli;

namespace {

// Seconds a command took.
template <class F>
double timed(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("grids, counts and domains that would not fit are bounded or refused up front") {
  Result r;
  // Grains of radius 4e-4 in pack_2d's box: the cell grid is bounded, the check quick and small.
  const double t = timed([&] {
    r = silt_cli("check " + scene_path("pack_2d") + " --set grains.0.radius_min=4e-4 --set grains.0.radius_max=4e-4");
  });
  CHECK(r.code == 0);
  CHECK(t < 10);
  // A billion grains, the documented maximum: refused at the count with the memory needed.
  r = silt_cli("check " + scene_path("pack_2d") + " --set grains.0.count=1000000000");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "--set:1:"));
  CHECK(contains(r.out, "GiB for 1000000000 grains"));
  // A periodic box a billion diameters long.
  r = silt_cli("check " + scene_path("shear3d_frictionless") + " --set 'domain.hi=[1e9, 12.04, 12.04]'");
  CHECK((r.code == 0 || r.code == 2));
  CHECK_FALSE(contains(r.out, "bad_alloc"));
  CHECK_FALSE(contains(r.out, "internal error"));
}

TEST_CASE("values no scene can supply are refused at their key") {
  Result r =
      silt_cli("check " + scene_path("collision_normal") + " --set 'grains.0.velocities=[[1e308, 0, 0], [0, 0, 0]]'");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "cross the whole domain"));
  r = silt_cli("check " + scene_path("collision_normal") + " --set grains.0.radius=1e-308");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "must be finite and positive"));
  r = silt_cli("check " + scene_path("collision_normal") + " --set 'grains.0.positions=[[nan, 0, 0], [1.6e-3, 0, 0]]'");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "nan is not a finite number"));
  r = silt_cli("check " + scene_path("collision_normal") + " --set 'grains.0.velocities=[[0.5, 0, 0], [nan, 0, 0]]'");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "not a finite number"));
  r = silt_cli("check " + scene_path("collision_normal") + " --set contact.contact_time=inf");
  CHECK(r.code == 2);
}

TEST_CASE("only regular files of a sane size are read") {
  silt::test::TempDir dir;
  Result r;
  const double t = timed([&] { r = silt_cli("check /dev/zero"); });
  CHECK(r.code == 4);
  CHECK(contains(r.out, "not a regular file"));
  CHECK(t < 5);
  r = silt_cli("check " + dir.path());
  CHECK(r.code == 4);
  CHECK(contains(r.out, "is a directory"));
  r = silt_cli("run " + scene_path("collision_normal") + " --restore /dev/zero");
  CHECK(r.code == 4);
  CHECK(contains(r.out, "not a regular file"));
  r = silt_cli("play /dev/zero");
  CHECK(r.code == 4);
}

TEST_CASE("an edited checkpoint with a recomputed checksum is refused as corrupt, exit 4") {
  silt::test::TempDir dir;
  auto sim = silt::test::simulation_from(silt::test::read_file(scene_path("collision_normal")));
  for (int k = 0; k < 10; ++k) REQUIRE(sim->step());
  silt::State s = sim->state();
  s.particle_x.clear();
  silt::write_checkpoint(dir / "bad.ckpt", sim->model(), s);
  const Result r = silt_cli("run " + scene_path("collision_normal") + " --steps 10 --restore " + (dir / "bad.ckpt"));
  CHECK(r.code == 4);
  CHECK(contains(r.out, "corrupt: particle_x has 0 entries"));
}

TEST_CASE("inputs the fuzzers found end in a clear message and the contract's exit code") {
  const std::string dir = std::string(SILT_SOURCE_DIR) + "/tests/fuzz/crashes/";
  const std::string pack =
      "run " + scene_path("pack_2d") + " --quiet --set grains.0.count=40 --set 'domain.hi=[8.0,8.0]'";
  const std::string shear =
      "run " + scene_path("shear3d_frictionless") + " --quiet --set grains.0.count=40 --set prepare.compress=false";
  struct Case {
    std::string args;
    int code;
  };
  const Case cases[] = {
      {pack + " --steps 3 --restore " + dir + "box_length_nan.ckpt", 3},
      {shear + " --steps 3 --restore " + dir + "lees_edwards_offset_far.ckpt", 3},
      {shear + " --steps 3 --restore " + dir + "lees_edwards_overflow.ckpt", 3},
      {pack + " --steps 3 --restore " + dir + "nbr_start_past_pairs.ckpt", 4},
      {pack + " --steps 3 --restore " + dir + "scalar_nan.ckpt", 4},
      {"check " + dir + "region_far_outside.toml", 0},
      {"check " + scene_path("pack_2d") + " --set 'grains[].radius=0.1'", 2},
      {"check " + scene_path("pack_2d") + " --set 'grains[99999999999].radius=0.1'", 2},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args);
    const Result r = silt_cli(c.args);
    CHECK(r.code == c.code);
    CHECK_FALSE(contains(r.out, "internal error"));
  }
}
