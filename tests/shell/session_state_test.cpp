// The shell's commands on the state: fields (from the field list), field, freeze.
#include "shell_fixtures.hpp"
#include "support/files.hpp"
#include "support/scenes.hpp"

#include <filesystem>
#include <fstream>

using namespace silt;
using test::Fixture;

TEST_CASE("fields lists every field of the state with its extent and size and field prints one") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 10"));
  f.take_out();
  REQUIRE(f.run("fields"));
  const std::string table = f.take_out();
  for (const FieldInfo& info : field_infos())
    if (info.module == "core" || info.module == "dem" || info.module == "shear")
      CHECK(table.find(info.name) != std::string::npos);
  CHECK(table.find("N*D") != std::string::npos);
  REQUIRE(f.run("field particle_v 1"));  // grain 1, by id: its three components
  const std::string v = f.take_out();
  CHECK(v.rfind("particle_v[1] = ", 0) == 0);
  CHECK(v.find("m/s") != std::string::npos);
  REQUIRE(f.run("field step"));
  CHECK(f.take_out() == "step = 10\n");
  REQUIRE(f.run("field particle_r"));
  CHECK(f.take_out().find("2 entries (N)") != std::string::npos);
  CHECK_FALSE(f.run("field particle_vv"));
  CHECK(f.take_err().find("did you mean 'particle_v'") != std::string::npos);
  CHECK_FALSE(f.run("field particle_v 7"));
  CHECK(f.take_err().find("no grain 7") != std::string::npos);
}

TEST_CASE("freeze stops the grains below a height and a saved checkpoint then makes a base") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("bounce_dry")));
  CHECK_FALSE(f.run("freeze w < 1"));
  CHECK_FALSE(f.run("freeze z = 1"));
  REQUIRE(f.run("freeze z < 1e9"));
  CHECK(f.take_out().find("froze 1 grain(s): 1 of 1 frozen") != std::string::npos);
  REQUIRE(f.run("run 100"));
  CHECK(f.value("p[0].vz") == 0);
  REQUIRE(f.run("save " + dir / "base.ckpt"));
  // A shear cell cannot hold frozen grains (a sheared gas: a shear cell without its preparation).
  const std::string gas = dir / "gas.toml";
  std::ofstream(gas) << test::frictional_gas(2, 0.5, 0.0, 0.06);
  REQUIRE(f.run("load " + gas));
  CHECK_FALSE(f.run("freeze y < 3"));
  CHECK(f.take_err().find("deforming box") != std::string::npos);
}

TEST_CASE("grains frozen by freeze stay frozen, with the state, when a key is set stopped or running") {
  // The scene has no frozen grains: a model compiled again from it differed from the running one,
  // so `set` threw the state away (and the freeze) when stopped and refused every key running.
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("bounce_dry")));
  REQUIRE(f.run("freeze z < 1e9"));
  REQUIRE(f.run("run 100"));
  REQUIRE(f.run("set gravity.magnitude 5"));
  CHECK(f.value("step") == 100);
  REQUIRE(f.run("run 100"));
  CHECK(f.value("p[0].vz") == 0);
  REQUIRE(f.run("start 100000000"));
  CHECK(f.run("set gravity.magnitude 7"));
  REQUIRE(f.run("stop"));
  CHECK(f.value("p[0].vz") == 0);
  REQUIRE(f.run("get gravity.magnitude"));
  CHECK(f.take_out().find('7') != std::string::npos);
  // Grains the scene froze are not carried: unfrozen by the scene, they fall.
  Fixture g;
  REQUIRE(g.run("load " + test::scene_path("bounce_dry")));
  REQUIRE(g.run("set grains.0.frozen true"));
  REQUIRE(g.run("run 10"));
  REQUIRE(g.run("set grains.0.frozen false"));
  REQUIRE(g.run("run 100"));
  CHECK(g.value("p[0].vz") < 0);
}

TEST_CASE("a restored state is kept when a key that is not steerable changes before the first step") {
  // It was made again from the scene, as a loaded scene's is: `silt run --restore X --set K=V`
  // kept it, the shell's `restore X`, `set K V` threw it away.
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("taylor_green_2d")));
  REQUIRE(f.run("set fluid.cells [16, 16]"));
  REQUIRE(f.run("set fluid.initial_velocity 2"));
  CHECK(f.value("fluid.ke") == doctest::Approx(1.0));
  REQUIRE(f.run("save " + dir / "start.ckpt"));
  REQUIRE(f.run("load " + test::scene_path("taylor_green_2d")));
  REQUIRE(f.run("set fluid.cells [16, 16]"));
  CHECK(f.value("fluid.ke") == doctest::Approx(0.25));
  REQUIRE(f.run("restore " + dir / "start.ckpt"));
  const std::string restored = f.hash();
  f.take_out();
  REQUIRE(f.run("set output.every 7"));  // not steerable: the scene compiled again
  CHECK(f.take_out().find("(state kept)") != std::string::npos);
  CHECK(f.hash() == restored);
  CHECK(f.value("fluid.ke") == doctest::Approx(1.0));
  // A loaded scene's own state at t = 0 is still made again from the scene as changed.
  REQUIRE(f.run("load " + test::scene_path("taylor_green_2d")));
  REQUIRE(f.run("set fluid.cells [16, 16]"));
  REQUIRE(f.run("set fluid.initial_velocity 2"));
  CHECK(f.take_out().find("made again") != std::string::npos);
}

TEST_CASE("save onto the stats file being written is refused and the stats are kept") {
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("stats " + dir / "s.csv" + " every 1"));
  REQUIRE(f.run("run 3"));
  CHECK_FALSE(f.run("save " + dir / "s.csv"));
  CHECK(f.take_err().find("the stats file being written, " + dir / "s.csv" + ", are the same file") !=
        std::string::npos);
  // A checkpoint is written to a temporary file made new beside it, then renamed: NAME.tmp
  // streaming the stats was emptied.
  REQUIRE(f.run("stats " + dir / "c.ckpt.tmp" + " every 1"));
  REQUIRE(f.run("run 3"));
  const std::string streamed = test::read_file(dir / "c.ckpt.tmp");
  REQUIRE(f.run("save " + dir / "c.ckpt"));
  CHECK(test::read_file(dir / "c.ckpt.tmp") == streamed);
  CHECK(std::filesystem::exists(dir / "c.ckpt"));
  REQUIRE(f.run("run 3"));
  REQUIRE(f.run("stats off"));
  for (const char* name : {"s.csv", "c.ckpt.tmp"}) {
    CAPTURE(name);
    std::ifstream in(dir / name);
    std::string header;
    std::getline(in, header);
    CHECK(header.rfind("t,", 0) == 0);
  }
}

TEST_CASE("a file named as a frame or a VTK file where they are written is refused, before or after them") {
  // (a stats file named frame_000001.png in the frames' directory was overwritten by that frame,
  // and removed by the next `frames` there as an earlier run's frame)
  test::TempDir dir;
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("stats " + dir / "frame_000001.png" + " every 1"));
  CHECK_FALSE(f.run("frames " + dir.path() + " every 1"));
  CHECK(f.take_err().find("the stats file being written") != std::string::npos);
  REQUIRE(f.run("stats " + dir / "index.pvd" + " every 1"));
  CHECK_FALSE(f.run("vtk " + dir.path() + " every 1"));
  f.take_err();
  REQUIRE(f.run("stats off"));
  REQUIRE(f.run("frames " + dir.path() + " every 1"));
  REQUIRE(f.run("vtk " + dir.path() + " every 1"));
  for (const char* name : {"frame_000002.png", "grains_000000.vtu", "index.pvd"}) {
    CAPTURE(name);
    CHECK_FALSE(f.run("stats " + dir / name));
    CHECK_FALSE(f.run("save " + dir / name));
  }
  REQUIRE(f.run("stats " + dir / "s.csv" + " every 1"));
  REQUIRE(f.run("save " + dir / "frame_1.ckpt"));
}

TEST_CASE("a force parameter set just after a freeze is taken by the next step") {
  // freeze leaves the state without a valid pair list; the forces made again for the new friction
  // ran the contact forces without one, and `set` was refused with an internal error.
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("chute")));
  REQUIRE(f.run("run 100"));
  REQUIRE(f.run("freeze z < 2"));
  CHECK(f.run("set contact.friction 0.1"));
  CHECK(f.take_err().find("internal error") == std::string::npos);
  REQUIRE(f.run("run 20"));
  CHECK(f.value("step") == 120);
}
