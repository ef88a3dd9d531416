// `silt check` and `silt run` on lubricated pastes: the dimensionless groups of a scene sheared at
// an imposed rate, the memory estimate and the refusal of a paste that does not fit, and the
// grains with no lubricated connection named in the run's output and summary.
#include <doctest/doctest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "shell/cli_fixtures.hpp"

using namespace silt::test;

namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("silt check on a paste sheared at an imposed rate: its time unit, St, and the factor's memory") {
  const Result r = silt_cli("check " + scene_path("paste_3d_shear"));
  CAPTURE(r.out);
  REQUIRE(r.code == 0);
  // No pressure is imposed: the time unit is 1 / gammadot (= 100), not eta / P; in reduced units,
  // without "s".
  CHECK(has(r.out, "time unit 1/gammadot = 100; a grain moves at most 0.05 of its radius a step\n"));
  CHECK_FALSE(has(r.out, "eta/P"));
  // St = m gammadot / (eta a): m = (4/3) pi 1^3 (density 1), gammadot = 0.01, eta = 1, a = 2.
  CHECK(has(r.out, "St = m gammadot / (eta a) = 0.020944"));
  CHECK(has(r.out, "kappa at the viscous stress eta gammadot = "));
  CHECK(has(r.out, "memory beyond the grains about "));
  CHECK(has(r.out, "connections, the initial grains at Phi = 0.45"));
  // With a pressure: kappa, Vi and St of the shear; in 2D the viscous time is eta a / P (P a
  // force per length).
  const Result s = silt_cli("check " + scene_path("paste_shear"));
  REQUIRE(s.code == 0);
  CHECK(has(s.out, "Vi = eta gammadot a / P = 0.01;"));
  CHECK(has(s.out, "St = m gammadot / (eta a) = "));
  CHECK(has(s.out, "time unit eta a/P = "));
}

TEST_CASE("silt check refuses up front a paste whose factor would not fit, saying how much it needs") {
#if defined(SILT_ASAN)
  return;  // AddressSanitizer reserves terabytes of address space: no program of it starts under ulimit -v
#endif
  // The 4,096 spheres of paste_3d_shear with the address space limited to 384 MiB (the program
  // takes about 250 MiB of it before it reads the scene, the grains 17 MiB): the paste's
  // estimate (0.2 GiB, 77 MiB of it the factor of the translations) is above what is left.
  const Result r = sh("ulimit -v 393216; " + silt_binary() + " check " + scene_path("paste_3d_shear"));
  CAPTURE(r.out);
  CHECK(r.code == 2);
  CHECK(has(r.out, "paste_3d_shear.toml:34:13:"));  // at lubrication.viscosity
  CHECK(has(r.out, "the paste needs about "));
  CHECK(has(r.out, "GiB, of which the Cholesky factor of Xi "));
  CHECK(has(r.out, "use fewer grains"));
  CHECK_FALSE(has(r.out, "bad_alloc"));
}

TEST_CASE("silt run names the grains with no lubricated connection in its output and its summary") {
  // Two grains touching and one far from them, at rest in a fixed box: grain 2 is alone at the
  // start and for the whole run, named once.
  write_file("cli_lonely_paste.toml", R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [10, 10]
periodic = [true, true]
[shear]
rate = 0.01
[contact]
model = "linear"
k_n = 1e4
[lubrication]
viscosity = 1.0
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[3.0, 5.0], [4.05, 5.0], [8.0, 2.0]]
)");
  const Result r = silt_cli("run cli_lonely_paste.toml --steps 20 --quiet --summary cli_lonely_paste.json");
  CAPTURE(r.out);
  REQUIRE(r.code == 0);
  const std::string note = "step 0: grain 2 has no lubricated connection";
  CHECK(has(r.out, "silt: warning: " + note));
  CHECK(r.out.find(note) == r.out.rfind(note));  // once
  const auto j = nlohmann::json::parse(read_file("cli_lonely_paste.json"));
  REQUIRE(j["warnings"].size() == 1);
  CHECK(j["warnings"][0].get<std::string>().rfind(note, 0) == 0);
  std::remove("cli_lonely_paste.toml");
  std::remove("cli_lonely_paste.json");
}

TEST_CASE("a paste's dry compression that fails names the dry model's parameters, not the paste's step") {
  // It advised lowering lubrication.dt_max, which the compression does not use (a non-finite
  // velocity at a pressure of 1e10, which is refused when read now: the compression's model names
  // run.dt as its step).
  const Result r = silt_cli("run " + scene_path("paste_shear") + " --set box.pressure=1e3 --steps 10 --threads 1 " +
                            "--quiet --summary cli_paste_prep_fail.json");
  CHECK(r.code == 3);
  CHECK(has(r.out, "numerical failure during the preparation"));
  CHECK(has(r.out, "increase contact.k_n"));
  CHECK_FALSE(has(r.out, "lubrication.dt"));
  std::remove("cli_paste_prep_fail.json");
  std::remove("cli_paste_prep_fail.last_good.ckpt");
}

TEST_CASE("silt run --restore: a failed compression's last good state is compressed on, the same packing to the bit") {
  // The last good state of a compression that failed (limits.max_overlap of 1e-3 reached at step
  // 3,371) was run as it was: the scene's run started from a half-compressed packing at its step.
  // Restored, the compression goes on from its step: the packing is an uninterrupted one's.
  const std::string dir = "cli_paste_resume";
  std::filesystem::create_directories(dir);
  const std::string scene = quarter_paste_scene("paste_iso", dir), lg = dir + "/failed.last_good.ckpt";
  const Result failed = silt_cli("run " + scene + " --threads 1 --quiet --set limits.max_overlap=1e-3 --steps 10 " +
                                 "--summary " + dir + "/failed.json");
  REQUIRE(failed.code == 3);
  REQUIRE(has(failed.out, "the compression's last good state written to"));
  const Result resumed =
      silt_cli("run " + scene + " --threads 1 --restore " + lg + " --steps 0 --save " + dir + "/resumed.ckpt");
  CHECK(resumed.code == 0);
  CHECK(has(resumed.out, "going on from step 3370 of " + lg));
  REQUIRE(silt_cli("run " + scene + " --threads 1 --quiet --steps 0 --save " + dir + "/fresh.ckpt").code == 0);
  CHECK(read_file(dir + "/resumed.ckpt") == read_file(dir + "/fresh.ckpt"));
  // The shell's restore goes on with it too; a scene that prepares nothing refuses it.
  const Result shell =
      silt_cli("play " + write_file(dir + "/restore.silt", "load " + scene + "\nhash\nrestore " + lg + "\nhash\n"));
  CHECK(shell.code == 0);
  CHECK(has(shell.out, "going on with the compression of " + lg + " from its step 3370"));
  const auto first = shell.out.find("state hash "), second = shell.out.rfind("state hash ");
  REQUIRE(first != second);
  CHECK(shell.out.substr(first, 27) == shell.out.substr(second, 27));
  std::string plain = read_file(scene);
  plain.replace(plain.find("compress = true\nphi = 0.8"), 25, "compress = false");
  plain.replace(plain.find("dilation = 1.1\n"), 15, "");
  const Result refused =
      silt_cli("run " + write_file(dir + "/plain.toml", plain) + " --threads 1 --quiet --restore " + lg + " --steps 1");
  CHECK(refused.code == 1);
  CHECK(has(refused.out, "a compression's state before its end (step 3370), and this scene prepares none"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("silt run: a compression cut short by prepare.max_steps says its own solid fraction, not the dilated one") {
  // It quoted the packing after prepare.dilation: 0.3605 at 1.1, 0.19387 at 1.5, of one compression.
  const std::string dir = "cli_paste_max_steps";
  std::filesystem::create_directories(dir);
  const std::string scene = quarter_paste_scene("paste_iso", dir);
  std::string said[2];
  for (int k = 0; k < 2; ++k) {
    const Result r = silt_cli("run " + scene + " --threads 1 --quiet --set prepare.max_steps=10 --steps 0 " +
                              "--set prepare.dilation=" + (k ? "1.5" : "1.0"));
    // (at 1.5 the grains are then too far apart for h_max: the paste's first solve refuses them, exit 3)
    const auto at = r.out.find("did not reach equilibrium in 10 steps (phi = ");
    REQUIRE(at != std::string::npos);
    said[k] = r.out.substr(at, r.out.find(')', at) - at);
  }
  CHECK(said[0] == said[1]);
  std::filesystem::remove_all(dir);
}

TEST_CASE("silt play: a value a paste does not use while it runs is said to act elsewhere") {
  // run.dt set in a running paste replied "from the next step" and changed nothing: the paste's
  // step is its own. So with box.mass_factor (its box is solved), and render.every in the shell.
  const std::string dir = "cli_paste_inert";
  std::filesystem::create_directories(dir);
  const std::string scene = quarter_paste_scene("paste_cyclic_alternating", dir);
  const Result r =
      silt_cli("play " + write_file(dir + "/inert.silt", "load " + scene +
                                                             "\nrun 2\nset run.dt 1e-5\nset box.mass_factor 5"
                                                             "\nset render.every 10\n"));
  CHECK(r.code == 0);
  CHECK(has(r.out, "note: run.dt sets the step of the dry preparation only"));
  CHECK(has(r.out, "note: box.mass_factor acts in the dry preparation only"));
  CHECK(has(r.out, "note: render.every is silt run's frame cadence"));
  std::filesystem::remove_all(dir);
}
