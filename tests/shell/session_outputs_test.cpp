// The shell as users of YADE or LAMMPS expect it: the scene's own run length, until static, the
// samples reset or windowed and written as they come, VTK files during runs, what a change
// discards, the observables and their units in help, reduced units.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "shell/cli_fixtures.hpp"
#include "shell/shell_fixtures.hpp"
#include "support/scenes.hpp"

using namespace silt;
using test::contains;
using test::Fixture;

TEST_CASE("run alone follows the scene's run length, until static stops at equilibrium or says why not") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));  // [run] time = 1e-3 s
  REQUIRE(f.run("run"));
  CHECK(f.value("t") == doctest::Approx(1e-3).epsilon(1e-6));
  f.take_out();
  CHECK_FALSE(f.run("run"));
  CHECK(contains(f.take_err(), "the scene's run length is reached"));
  CHECK_FALSE(f.run("run until static"));
  CHECK(contains(f.take_err(), "no box.pressure"));
  REQUIRE(f.run("run 2"));  // an explicit length goes on
  // Where nothing can come to rest, refused (a cyclic scene's ran without end).
  test::TempDir dir;
  const std::string box = R"([scene]
dimension = 2
[domain]
lo = [0.0, 0.0]
hi = [10.0, 10.0]
periodic = [true, true]
[contact]
model = "linear"
k_n = 1e3
[[grains]]
count = 40
radius = 0.5
placement = "random"
[run]
dt_over_tc = 0.05
steps = 10
[box]
pressure = 1.0
)";
  std::ofstream(dir / "cycled.toml") << box << "cycle = \"biaxial\"\ncycle_period = 10.0\n";
  std::ofstream(dir / "sheared.toml") << box << "[shear]\nrate = 0.1\n";
  REQUIRE(f.run("load " + dir / "cycled.toml"));
  CHECK_FALSE(f.run("run until static"));
  CHECK(contains(f.take_err(), "the imposed stresses cycle (box.cycle), and a packing under them is never at rest"));
  REQUIRE(f.run("load " + dir / "sheared.toml"));
  CHECK_FALSE(f.run("run until static"));
  CHECK(contains(f.take_err(), "the imposed shear rate (shear.rate) keeps the packing flowing"));
  // A scene asking for it is refused at its key.
  std::string at_rest = box;
  at_rest.replace(at_rest.find("steps = 10"), 10, "steps = 10\nstop_when_static = true");
  std::ofstream(dir / "cycled_static.toml") << at_rest << "cycle = \"biaxial\"\ncycle_period = 10.0\n";
  CHECK_FALSE(f.run("load " + dir / "cycled_static.toml"));
  CHECK(contains(f.take_err(), "a packing under cyclic stresses (box.cycle) is never at rest"));
}

TEST_CASE("stats reset, stats since T, and stats FILE every N writing as the run goes") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 10"));  // collision_normal samples every step: steps 0 .. 10
  REQUIRE(f.run("stats " + (dir / "s.csv") + " every 2"));
  CHECK(contains(f.take_out(), "(11 sample(s) so far), every 2 steps"));
  REQUIRE(f.run("run 10"));
  // Header, the 11 earlier samples, then steps 12, 14, ..., 20.
  const std::string csv = test::read_file(dir / "s.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 11 + 5);
  f.take_out();
  REQUIRE(f.run("stats since 1.2e-5"));
  CHECK(contains(f.take_out(), "      5\n"));  // steps 12 .. 20
  REQUIRE(f.run("stats reset"));
  CHECK(contains(f.take_out(), "stats reset: 16 sample(s) discarded; " + (dir / "s.csv") + " closed as it is"));
  CHECK_FALSE(f.run("stats"));
  CHECK(contains(f.take_err(), "no samples yet"));
  CHECK_FALSE(f.run("stats since 1e9"));
  // The file keeps its rows (it was opened again and emptied for the new series).
  REQUIRE(f.run("run 4"));
  CHECK(test::read_file(dir / "s.csv") == csv);
  CHECK_FALSE(f.run("stats off"));  // it goes to no file now
  CHECK_FALSE(f.run("stats a.csv every 0"));
  f.take_err();
  CHECK_FALSE(f.run("stats every"));  // it started a file named "every"
  CHECK(contains(f.take_err(), "'every' is a word of the command, not a file"));
  CHECK_FALSE(std::filesystem::exists("every"));
  // A file already there is replaced, and the reply says so (it said nothing).
  REQUIRE(f.run("stats " + (dir / "s.csv")));
  CHECK(contains(f.take_out(), "; it replaces the file that was there (" + std::to_string(csv.size()) + " bytes)"));
  REQUIRE(f.run("stats " + (dir / "new.csv")));
  CHECK_FALSE(contains(f.take_out(), "replaces"));
}

TEST_CASE("the VTK index's times run forward after a restore goes back, the files of the branch left kept") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 10"));
  REQUIRE(f.run("save " + (dir / "c10.ckpt")));
  REQUIRE(f.run("vtk " + (dir / "v") + " every 5"));
  REQUIRE(f.run("run 10"));  // t = 10, 15, 20 dt
  REQUIRE(f.run("restore " + (dir / "c10.ckpt")));
  REQUIRE(f.run("run 5"));  // t = 10, 15 dt again
  REQUIRE(f.run("vtk off"));
  const std::string pvd = test::read_file(dir / "v/index.pvd");
  std::vector<double> times;
  for (size_t at = pvd.find("part=\"0\""); at != std::string::npos; at = pvd.find("part=\"0\"", at + 1)) {
    const size_t t = pvd.rfind("timestep=\"", at) + 10;
    times.push_back(std::stod(pvd.substr(t)));
  }
  REQUIRE(times.size() == 2);
  CHECK(times[0] < times[1]);
  CHECK(contains(pvd, "grains_000003.vtu"));
  CHECK(contains(pvd, "grains_000004.vtu"));
  CHECK(std::filesystem::exists(dir / "v/grains_000002.vtu"));  // of the branch left: kept, not listed
  CHECK_FALSE(contains(pvd, "grains_000002.vtu"));
}

TEST_CASE("vtk DIR every N writes during runs, a change that discards the run says what it discarded") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("pack_2d")));
  REQUIRE(f.run("vtk " + (dir / "v") + " every 5"));
  REQUIRE(f.run("run 10"));
  REQUIRE(f.run("vtk off"));
  CHECK(contains(f.take_out(), "vtk off (3 written)"));
  CHECK(std::filesystem::exists(dir / "v/index.pvd"));
  CHECK(std::filesystem::exists(dir / "v/grains_000002.vtu"));
  REQUIRE(f.run("set grains.0.count 100"));
  CHECK(contains(f.take_out(), "discarded: the run to t = "));
  // The same directory again: the earlier run's numbered files go (they mixed with the new ones in
  // a series opened by name), as frames' do; others stay.
  test::write_file(dir / "v/notes.txt", "mine");
  REQUIRE(f.run("vtk " + (dir / "v") + " every 5"));
  CHECK(contains(f.take_out(), "(6 file(s) of an earlier run removed)"));  // 3 of grains, 3 of contacts
  CHECK_FALSE(std::filesystem::exists(dir / "v/grains_000002.vtu"));
  CHECK(std::filesystem::exists(dir / "v/notes.txt"));
}

TEST_CASE("help lists the observables with their units, reduced units label none") {
  Fixture f;
  REQUIRE(f.run("help"));
  const std::string all = f.take_out();
  const size_t at = all.find("\nstress.AB ");
  REQUIRE(at != std::string::npos);
  const std::string line = all.substr(at + 1, all.find('\n', at + 1) - at - 1);
  CHECK(contains(line, " Pa "));  // the unit column
  CHECK(contains(all, "p[K].vA"));
  REQUIRE(f.run("load " + test::scene_path("chute")));  // scene.units = "reduced"
  f.take_out();
  REQUIRE(f.run("print ke"));
  const std::string ke = f.take_out();
  CHECK(contains(ke, "ke = "));
  CHECK_FALSE(contains(ke, "J"));
  REQUIRE(f.run("get domain.hi"));
  CHECK_FALSE(contains(f.take_out(), " m\n"));
}

TEST_CASE("watch off during a background run, a field's index past its end, outputs every N across runs") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("pack_2d")));
  // The run's watch hook read the observer `watch off` had emptied: a segmentation fault.
  REQUIRE(f.run("watch t every 10"));
  REQUIRE(f.run("start 100000"));
  REQUIRE(f.run("watch off"));
  REQUIRE(f.run("stop"));
  // (at + 1) * 2 overflowed and passed the bounds check: a read far out of the array.
  CHECK_FALSE(f.run("field pair_f 5000000000000000000"));
  CHECK(contains(f.take_err(), "pair_f has"));
  // Twenty `run 1` with frames every 10 wrote a frame at the start of each run: 22 frames.
  REQUIRE(f.run("reset"));
  REQUIRE(f.run("frames " + (dir / "fr") + " every 10"));
  for (int k = 0; k < 20; ++k) REQUIRE(f.run("run 1"));
  REQUIRE(f.run("frames off"));
  CHECK(contains(f.take_out(), "frames off (3 written)"));  // steps 0, 10 and 20
  // Another state at the step of the last frame (a reset, another scene, a restore) was skipped:
  // the new scene's first frame was never written.
  REQUIRE(f.run("frames " + (dir / "fr2") + " every 10"));
  REQUIRE(f.run("run 10"));  // steps 0 and 10
  REQUIRE(f.run("save " + (dir / "at10.ckpt")));
  REQUIRE(f.run("reset"));
  REQUIRE(f.run("run 10"));  // 0 and 10 of the reset state
  REQUIRE(f.run("restore " + (dir / "at10.ckpt")));
  REQUIRE(f.run("run 10"));  // 10 restored, and 20
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 10"));  // 0 and 10 of the new scene
  REQUIRE(f.run("frames off"));
  CHECK(contains(f.take_out(), "frames off (8 written)"));
}

TEST_CASE("set: a kept state keeps its samples, and before the first step the state is made again from the scene") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("pack_2d")));
  REQUIRE(f.run("stats " + (dir / "st.csv") + " every 10"));
  REQUIRE(f.run("run 100"));
  // A change that keeps the state closed the stats file and discarded the samples, saying only
  // "(state kept)".
  REQUIRE(f.run("set render.width 500"));
  CHECK(contains(f.take_out(), "(state kept)"));
  REQUIRE(f.run("run 10"));
  REQUIRE(f.run("stats"));
  CHECK(contains(f.take_out(), "     12\n"));  // steps 0, 10, ..., 110
  const std::string csv = test::read_file(dir / "st.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 12);
  // Initial positions changed before the first step were kept as "(state kept)" and did nothing.
  Fixture g;
  REQUIRE(g.run("load " + test::scene_path("collision_normal")));
  REQUIRE(g.run("set grains[0].positions [[-5e-3, 0, 0], [5e-3, 0, 0]]"));
  CHECK(contains(g.take_out(), "the state at t = 0 made again"));
  CHECK(g.value("p[0].x") == doctest::Approx(-5e-3));
}
