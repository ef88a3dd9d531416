// The shear workflow through the command line: procedure O, --save / --restore of the prepared
// packing, the velocity profile in the summary.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "silt/observables.hpp"
#include "support/scenes.hpp"

namespace {

const char* kShear = R"(
[scene]
dimension = 2
seed = 4
[domain]
lo = [0, 0]
hi = [16, 16]
periodic = [true, true]
[box]
pressure = 1.0
controlled = [false, true]
[shear]
inertial_number = 0.1
[prepare]
compress = true
[contact]
model = "linear"
k_n = 1e3
damping = 0.9
friction = 0.0
[[grains]]
count = 150
radius_min = 0.35
radius_max = 0.5
placement = "random"
[run]
dt_over_tc = 0.05
time = 60.0
static_force_tol = 1e-3
static_stress_tol = 1e-3
static_ke_tol = 1e-7
[output]
observe = ["t", "gamma", "I", "mu", "phi", "stress.yy"]
every = 100
)";

int run(const std::string& args, std::string* out = nullptr) {
  const std::string cmd = silt::test::silt_binary() + " " + args + " 2>&1";
  std::FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  std::string text;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) text.append(buf, n);
  const int status = pclose(p);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("procedure O: a prepared packing is static at P, at rest, unsheared, with the scene's boundaries") {
  const silt::Model m = silt::test::model_from(kShear);
  silt::PreparationReport rep;
  const silt::State s = silt::prepare_packing(m, 2, &rep);
  CHECK(rep.end == silt::RunEnd::kStatic);
  CHECK(s.t == 0);
  CHECK(s.step == 0);
  CHECK(s.shear_strain == 0);
  CHECK(s.box.lees_edwards);
  CHECK(s.shear_rate == doctest::Approx(m.shear.rate));
  const silt::Measurements q = silt::measure(m, s);
  CHECK(q.ke == 0);
  // Isotropic: both lengths were controlled, so both stresses are at P within the tolerance.
  CHECK(std::abs(q.stress[0][0] - 1) < 1.5e-3);
  CHECK(std::abs(q.stress[1][1] - 1) < 1.5e-3);
  CHECK(q.phi > 0.8);  // frictionless disks jam near 0.84; the gas started at 0.33
}

TEST_CASE("silt run: prepare, save, restore and shear with a linear mean velocity profile") {
  std::string out;
  std::ofstream("cli_shear.toml") << kShear;
  REQUIRE(run("run cli_shear.toml --steps 0 --save cli_shear_prep.ckpt --summary cli_shear_prep.json", &out) == 0);
  CHECK(out.find("prepared in") != std::string::npos);
  {
    // The compression's stages apart from the run's (which were its: 6 s of contact forces in a
    // run of 0.1 s).
    std::ifstream pin("cli_shear_prep.json");
    const auto p = nlohmann::json::parse(pin);
    CHECK(p["preparation"]["steps"].get<int64_t>() > 0);
    CHECK(p["preparation"]["stages"].contains("contact_forces"));
    double run_stages = 0;
    for (const auto& [name, seconds] : p["stages"].items()) run_stages += seconds.get<double>();
    CHECK(run_stages <= p["wall_s"].get<double>());
  }
  REQUIRE(run("run cli_shear.toml --quiet --restore cli_shear_prep.ckpt --summary cli_shear.json --average-from 20 "
              "--observe t,gamma,I,box.Ly",
              &out) == 0);
  CHECK(out.find("prepared") == std::string::npos);  // restored, not prepared again
  std::ifstream in("cli_shear.json");
  const auto j = nlohmann::json::parse(in);
  const silt::Model m = silt::test::model_from(kShear);
  const double gd = 0.1 / std::sqrt(m.m_a);  // I = gammadot sqrt(m / P), P = 1, m of the largest grain
  CHECK(j["observables"]["I"]["mean"].get<double>() == doctest::Approx(0.1));
  CHECK(j["observables"]["gamma"]["last"].get<double>() ==
        doctest::Approx(gd * j["observables"]["t"]["last"].get<double>()));
  // The time-averaged profile follows the imposed flow v_x = gammadot (y - lo): slab centres at
  // (k + 1/2) L_y / n. Each slab within 0.05 gammadot L_y of it (about 3 errors of the mean here).
  const auto& prof = j["profiles"]["vx(y)"];
  const size_t n = prof["mean"].size();
  REQUIRE(n >= 4);
  const double ly = j["observables"]["box.Ly"]["mean"].get<double>();
  for (size_t k = 0; k < n; ++k) {
    const double y = prof["x"][k].get<double>();
    CHECK(y == doctest::Approx((k + 0.5) / n));
    CHECK(std::abs(prof["mean"][k].get<double>() - gd * ly * y) < 0.05 * gd * ly);
  }
  // Other run parameters are no error, but each is named, on stderr and in the summary.
  REQUIRE(run("run cli_shear.toml --quiet --steps 10 --restore cli_shear_prep.ckpt --set shear.inertial_number=0.05 "
              "--summary cli_shear_w.json",
              &out) == 0);
  CHECK(out.find("warning: shear.inertial_number = 0.1 in the checkpoint, 0.05 in the scene") != std::string::npos);
  std::ifstream win("cli_shear_w.json");
  const auto w = nlohmann::json::parse(win);
  REQUIRE(w["warnings"].size() == 1);
  CHECK(w["warnings"][0].get<std::string>().find("shear.inertial_number") == 0);
  // A checkpoint of these grains under another scene's run parameters restores; another system does not.
  CHECK(run("run " + silt::test::scene_path("pack_2d") + " --steps 1 --restore cli_shear_prep.ckpt", &out) == 4);
}

TEST_CASE("silt run: a preparation cut short by prepare.max_steps is said on stderr and in the summary") {
  std::string out;
  std::string scene = kShear;
  scene.replace(scene.find("compress = true\n"), 16, "compress = true\nmax_steps = 50\n");
  std::ofstream("cli_shear_short.toml") << scene;
  REQUIRE(run("run cli_shear_short.toml --quiet --steps 2 --summary cli_shear_short.json", &out) == 0);
  CHECK(out.find("warning: prepare.max_steps: the compression did not reach equilibrium in 50 steps (phi = ") !=
        std::string::npos);
  std::ifstream in("cli_shear_short.json");
  const auto j = nlohmann::json::parse(in);
  bool named = false;
  for (const auto& w : j["warnings"]) named |= w.get<std::string>().find("prepare.max_steps") == 0;
  CHECK(named);
  std::remove("cli_shear_short.toml");
  std::remove("cli_shear_short.json");
}
