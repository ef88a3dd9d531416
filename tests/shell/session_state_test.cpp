// The shell's commands on the state: fields (from the field list), field, freeze.
#include "shell_fixtures.hpp"
#include "support/scenes.hpp"

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
