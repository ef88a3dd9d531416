// What a user types, pipes, schedules or crafts never crashes or hangs silt: each reproducer ends
// in a clear message and the exit code of the contract (INTERFACE.md).
#include <doctest/doctest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "core/machine.hpp"
#include "shell/cli_fixtures.hpp"
#include "shell/shell_fixtures.hpp"
#include "silt/input_files.hpp"
#include "silt/io.hpp"

using silt::test::contains;
using silt::test::Result;
using silt::test::scene_path;
using silt::test::silt_cli;
using silt::test::write_file;

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
  // And 1e-4, which ended in std::bad_alloc.
  r = silt_cli("check " + scene_path("pack_2d") + " --set grains.0.radius_min=1e-4 --set grains.0.radius_max=1e-4");
  CHECK(r.code == 0);
  CHECK(contains(r.out, "\nok"));
  // A billion grains, the documented maximum: refused at the count with the memory needed.
  r = silt_cli("check " + scene_path("pack_2d") + " --set grains.0.count=1000000000");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "--set:1:"));
  CHECK(contains(r.out, "GiB for 1000000000 grains"));
  // A periodic box a billion diameters long: its cell grid bounded by the grains, a few MiB.
  r = silt_cli("check " + scene_path("shear3d_frictionless") + " --set 'domain.hi=[1e9, 12.04, 12.04]'");
  CHECK(r.code == 0);
  CHECK(contains(r.out, "\nok"));
  CHECK_FALSE(contains(r.out, "bad_alloc"));
  CHECK_FALSE(contains(r.out, "internal error"));
}

TEST_CASE("values no scene can supply are refused at their key") {
  Result r =
      silt_cli("check " + scene_path("collision_normal") + " --set 'grains.0.velocities=[[1e308, 0, 0], [0, 0, 0]]'");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "cross the whole domain"));
  // The speed is computed without squaring it (1e308^2 overflows): the message gives it.
  CHECK(contains(r.out, "grain 0 starts at 1e+308 m/s"));
  // A spin alike, at its key (it was an energy "not finite" at the file's first line).
  r = silt_cli("check " + scene_path("collision_normal") +
               " --set 'grains.0.angular_velocities=[[0, 1e300, 0], [0, 0, 0]]'");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "--set:1:"));
  CHECK(contains(r.out, "grain 0 starts spinning at 1e+300 rad/s"));
  r = silt_cli("check " + scene_path("collision_normal") +
               " --set 'grains.0.velocities=[[3e200, 4e200, 0], [0, 0, 0]]'");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "grain 0 starts at 5e+200 m/s"));
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
  // Values a run could only fail with: a weight that alone overlaps a resting grain beyond
  // limits.max_overlap (it printed a weight overlap of inf, `ok`, and the run failed at its first
  // step); a pressure that presses every contact by more than a diameter (kappa below 1: it failed
  // at step 1 with a non-finite velocity, advising a shorter step); 3D Hertz's Poisson ratio of -1
  // (E~ = E / (1 - nu^2) infinite), now outside its range.
  struct Refused {
    const char* scene;
    const char* set;
    std::vector<const char*> says;
  };
  for (const Refused& c :
       {Refused{"silo",
                "gravity.magnitude=1e300",
                {"--set:1:19: a grain's weight alone", "reduce the gravity below 4.081e+05 m/s^2"}},
        Refused{"pack_2d",
                "box.pressure=1e10",
                {"--set:1:14: the pressure 1e+10 N/m gives a stiffness number kappa = 1e-06 below 1",
                 "kappa is 1 at 1e+04 N/m"}},
        // (an imposed shear stress alike: it failed at step 1 advising a larger k_n)
        Refused{"shear2d_dry",
                "shear.stress=1e300",
                {"--set:1:14: the shear stress 1e+300 N/m gives a stiffness number kappa = 1e-296",
                 "kappa is 1 at 1e+04 N/m"}},
        // (a stress cycle at its peak, P (1 + 2 d) biaxial: kappa 1.11 at the mean passed)
        Refused{"paste_cyclic_biaxial",
                "box.pressure=9000",
                {"--set:1:14: the cycle's largest stress 1.08e+04 gives a stiffness number "
                 "kappa = 0.926 below 1"}},
        Refused{"shear3d_frictionless", "contact.poisson_ratio=-1", {"(-1, 0.5)"}},
        // (a value begun as a TOML string and left unfinished was kept, its quote included)
        Refused{"chute", "'scene.name=\"unfinished'", {"--set:1:12: cannot read the value of scene.name"}},
        Refused{"chute", "bogus.key=3", {"--set:1:1: unknown key 'bogus.key'"}},
        // (the packing fell through its periodic box, its fall counted as pressure)
        Refused{"pack_2d",
                "gravity.magnitude=1",
                {"--set:1:19: gravity along y, a periodic length the pressure controls"}}}) {
    CAPTURE(c.set);
    r = silt_cli("check " + scene_path(c.scene) + " --set " + c.set);
    CHECK(r.code == 2);
    for (const char* part : c.says) CHECK(contains(r.out, part));
  }
  CHECK(silt_cli("check " + scene_path("silo") + " --set gravity.magnitude=3e5").code == 0);
}

namespace {

// A grain above a wall, hooke contacts: the wall's spring and the dashpot as given (lines 9, 13).
const char* kWallScene = R"([scene]
dimension = 3
[domain]
lo = [-5, -5, 0]
hi = [5, 5, 5]
[contact]
model = "hooke"
k_n = 100
gamma_n = {gamma}
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
k_n = {wall_k}
[[grains]]
radius = 0.5
density = 1000
placement = "explicit"
positions = [[0, 0, 1]]
[run]
dt = 1e-4
)";

}  // namespace

TEST_CASE("a contact scale out of the numbers' range is refused at the key that caused it") {
  silt::test::TempDir dir;
  // A wall's spring of 1e308 in series with the grains' 100 N/m: 200 N/m, twice the grains' (2 k_w
  // k_g / (k_w + k_g) overflowed, and the scene was refused as "the contacts' stiffness is inf").
  std::string text = silt::test::fill(kWallScene, {{"gamma", 0.0}, {"wall_k", 1e308}});
  Result r = silt_cli("check " + write_file(dir / "wall.toml", text));
  CHECK(r.code == 0);
  // A dashpot of 1e308 per second on grains of 524 kg: the damping ratio overflows.
  text = silt::test::fill(kWallScene, {{"gamma", 1e308}, {"wall_k", 100.0}});
  r = silt_cli("check " + write_file(dir / "dashpot.toml", text));
  CHECK(r.code == 2);
  CHECK(contains(r.out, "dashpot.toml:9:11: the contacts' damping ratio is inf"));
  // On the command line, at the --set that gave the number: a contact time of 1e-200 s makes the
  // spring-dashpot's stiffness infinite; a modulus of 1e-320 Pa makes the Hertz contact time so.
  r = silt_cli("check " + scene_path("collision_normal") +
               " --set contact.friction=0.2 --set contact.contact_time=1e-200");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "--set:2:"));
  CHECK(contains(r.out, "the contacts' stiffness is inf"));
  r = silt_cli("check " + scene_path("shear3d_frictionless") + " --set contact.young_modulus=1e-320");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "--set:1:"));
  CHECK(contains(r.out, "contact time is inf"));
  // Grains of 1e-56 m: each mass is a number, and so is the reduced mass (the product of two masses
  // underflowed, and the scene was refused as "the contacts' reduced mass is 0").
  r = silt_cli("check " + scene_path("collision_normal") + " --set contact.friction=0.2 --set grains.0.radius=1e-56");
  CHECK(r.code == 0);
  // A density of 1e-300: the reduced mass is subnormal and sqrt(m* k) under the dashpot 0, at the
  // density (it was located at the scene's radius line, then at contact.restitution).
  r = silt_cli("check " + scene_path("collision_normal") + " --set contact.friction=0.2 --set grains.0.density=1e-300");
  CHECK(r.code == 2);
  CHECK(contains(r.out, "--set:2:"));
  CHECK(contains(r.out, "the contacts' damping ratio is inf"));
}

TEST_CASE("a wall softer than the grains is named: its weight check at load, its overlap in a run") {
  // A grain of 524 kg on a wall whose spring (in series with the grains' 1e6 N/m) is the soft one.
  // The weight was checked against the grains' law alone, and an overlap with the wall was
  // reported as "a neighbour or a wall", advising contact.k_n.
  const char* scene = R"([scene]
dimension = 3
[domain]
lo = [-5, -5, 0]
hi = [5, 5, 5]
[gravity]
magnitude = 9.81
[contact]
model = "hooke"
k_n = 1e6
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
k_n = {wall_k}
[[grains]]
radius = 0.5
density = 1000
placement = "explicit"
positions = [[0, 0, 1.5]]
velocity = "explicit"
velocities = [[0, 0, -10]]
[run]
dt = 1e-4
steps = 20000
)";
  silt::test::TempDir dir;
  // 1e3 N/m (2e3 with the grains' spring, as two moduli mix): the weight presses the grain 5 radii in.
  Result r = silt_cli("check " + write_file(dir / "soft.toml", silt::test::fill(scene, {{"wall_k", 1e3}})));
  CHECK(r.code == 2);
  CHECK(contains(
      r.out,
      "soft.toml:14:7: the weight of grain 0 (of grains[0]) alone presses it into walls[0] by 5.14 of its radius"));
  // 1e5 N/m holds the weight (0.06 of a radius) but not the impact at 10 m/s.
  const std::string run = write_file(dir / "impact.toml", silt::test::fill(scene, {{"wall_k", 1e5}}));
  CHECK(silt_cli("check " + run).code == 0);
  r = silt_cli("run " + run + " --threads 1 --quiet");
  CHECK(r.code == 3);
  CHECK(contains(r.out, "stage wall_forces: grain 0 overlaps walls[0] by"));
  CHECK(contains(r.out, "increase walls[0].k_n (stiffer contacts)"));
  // A wall far stiffer than the grains: the grains' spring is the one to stiffen (the series spring
  // is at most twice it), not the wall's, which the message named.
  const std::string hard = write_file(dir / "hard.toml", silt::test::fill(scene, {{"wall_k", 1e9}}));
  r = silt_cli("run " + hard + " --threads 1 --quiet");
  CHECK(r.code == 3);
  CHECK(contains(r.out, "stage wall_forces: grain 0 overlaps walls[0] by"));
  CHECK(contains(r.out, "increase contact.k_n (stiffer contacts)"));
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

TEST_CASE("scenes, scripts and checkpoints are read only up to the size any of them can have") {
  silt::test::TempDir dir;
  // Sparse files: as long as they say, without taking the disk space.
  auto sparse = [&](const std::string& name, std::uintmax_t bytes, const std::string& head) {
    const std::string path = dir / name;
    std::ofstream(path, std::ios::binary) << head;
    std::filesystem::resize_file(path, bytes);
    return path;
  };
  Result r;
  const std::string scene = sparse("big.toml", silt::kMaxTextFileBytes + 1, "[scene]\n");
  const double t = timed([&] { r = silt_cli("check " + scene); });
  CHECK(r.code == 4);
  CHECK(contains(r.out, "more than any scene file can have here"));
  CHECK(t < 5);
  const std::string script = sparse("big.silt", silt::kMaxTextFileBytes + 1, "print t\n");
  r = silt_cli("play " + script);
  CHECK(r.code == 4);
  CHECK(contains(r.out, "more than any script can have here"));
  // A checkpoint larger than the machine's memory: no system that runs here has one.
  const std::string ckpt = sparse("big.ckpt", silt::max_checkpoint_bytes() + 1, "SILTCKPT");
  r = silt_cli("run " + scene_path("collision_normal") + " --steps 1 --restore " + ckpt);
  CHECK(r.code == 4);
  CHECK(contains(r.out, "more than any checkpoint can have here"));
  // The shell's source and restore, through the same check.
  silt::test::Fixture f;
  REQUIRE(f.run("load " + scene_path("collision_normal")));
  CHECK_FALSE(f.run("source " + script));
  CHECK(contains(f.take_err(), "more than any script can have here"));
  CHECK_FALSE(f.run("restore " + ckpt));
  CHECK(contains(f.take_err(), "more than any checkpoint can have here"));
  CHECK_FALSE(f.run("load " + scene));
  CHECK(contains(f.take_err(), "more than any scene file can have here"));
}

TEST_CASE("a checkpoint is smaller than the memory its system needs, which the machine's bounds") {
  // Why the machine's memory bounds a checkpoint: a checkpoint holds one copy of the state, and
  // compiling refuses a system whose estimate (the state twice, its pairs and cells) does not fit.
  silt::test::TempDir dir;
  for (const char* name : {"collision_normal", "pack_2d", "silo"}) {
    CAPTURE(name);
    auto sim = silt::test::simulation_from(silt::test::read_file(scene_path(name)));
    for (int k = 0; k < 20; ++k) REQUIRE(sim->step());
    silt::write_checkpoint(dir / "c.ckpt", sim->model(), sim->state());
    CHECK(static_cast<double>(std::filesystem::file_size(dir / "c.ckpt")) < silt::estimated_memory_bytes(sim->model()));
  }
  CHECK(static_cast<double>(silt::max_checkpoint_bytes()) >= silt::available_memory_bytes());
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
  // A step count of 2^63 - 1 overflowed at the first step (UBSan, in the energy check).
  s = sim->state();
  s.step = std::numeric_limits<int64_t>::max();
  silt::write_checkpoint(dir / "last_step.ckpt", sim->model(), s);
  const Result last =
      silt_cli("run " + scene_path("collision_normal") + " --steps 10 --restore " + (dir / "last_step.ckpt"));
  CHECK(last.code == 4);
  CHECK(contains(last.out, "corrupt: step = 9223372036854775807 is outside [0, 9e18]"));
  s = sim->state();
  s.nbr_builds = -1;  // every integer scalar is a count
  silt::write_checkpoint(dir / "builds.ckpt", sim->model(), s);
  const Result builds =
      silt_cli("run " + scene_path("collision_normal") + " --steps 10 --restore " + (dir / "builds.ckpt"));
  CHECK(builds.code == 4);
  CHECK(contains(builds.out, "corrupt: nbr_builds = -1 is outside [0, 9e18]"));
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
      {pack + " --steps 3 --restore " + dir + "step_count_max.ckpt", 4},
      // The sanitizer build's access check (one thread: the serial executor) stopped this run at
      // step 251 with an internal error.
      {"run " + scene_path("collision_normal") + " --quiet --threads 1 --steps 300 --restore " + dir +
           "candidate_travel_twice.ckpt",
       0},
      // A state whose pair list is not valid, restored under other force parameters than its
      // own: the forces' refresh ran the contact forces without a list (an internal error).
      {shear + " --threads 1 --steps 3 --restore " + dir + "stale_forces_without_pair_list.ckpt", 0},
      // Restored under other force parameters with a pair that cannot touch holding a spring: the
      // access check found the refresh's pair loop choosing the contact candidates itself.
      {pack + " --threads 1 --steps 3 --restore " + dir + "candidates_chosen_in_refresh.ckpt", 0},
      // A stored factor whose column start lies far past its entries, then smaller ones: read as
      // an index before the later starts were seen (UBSan float-cast-overflow). Refused.
      {"run " + scene_path("paste_shear") + " --quiet --set grains.0.count=80 --threads 1 --steps 3 --restore " + dir +
           "paste_factor_column_far.ckpt",
       4},
      // The solves its stored factor has served given as 1e308: cast to int when the factor was
      // made again (UBSan float-cast-overflow). Refused.
      {"run " + scene_path("paste_shear") + " --quiet --set grains.0.count=80 --threads 1 --steps 3 --restore " + dir +
           "paste_factor_age_far.ckpt",
       4},
      {"check " + dir + "region_far_outside.toml", 0},
      {"check " + dir + "fluid_with_shear_table.toml", 2},
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

TEST_CASE("silt play: frames that cannot be written fail the script with exit 4, as silt run does") {
  // A frame's path taken by a directory: the writer stopped, the shell said nothing, play exited 0.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "silt_play_frames_fail";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "fd" / "frame_000001.png");
  const std::string script = write_file("cli_frames_fail.silt", "load " + scene_path("pack_2d") + "\nframes " +
                                                                    (dir / "fd").string() + " every 10\nrun 50\n");
  const Result r = silt_cli("play " + script);
  CHECK(r.code == 4);
  CHECK(r.out.find("frames stopped (the run went on)") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "an output given the scene's own name is refused, the scene left whole, and a script's byte order mark is "
    "skipped") {
  // `--stats scene.toml` opened the scene for writing and emptied it; so did the shell's stats,
  // save and render.
  const std::string scene = write_file("cli_own_name.toml", test::read_file(scene_path("pack_2d")));
  const std::string before = test::read_file(scene);
  for (const std::string opt : {"--stats ", "--summary ", "--save "}) {
    CAPTURE(opt);
    const Result r = silt_cli("run " + scene + " --steps 2 --quiet " + opt + scene);
    CHECK(r.code == 4);
    CHECK(contains(r.out, "it is the scene file"));
    CHECK(test::read_file(scene) == before);
  }
  const std::string script = write_file("cli_own_name.silt", "\xEF\xBB\xBFload " + scene + "\nsave " + scene +
                                                                 "\nstats " + scene + "\nrender " + scene + "\n");
  const Result r = silt_cli("play --keep-going " + script);
  CHECK(r.code == 4);
  CHECK_FALSE(contains(r.out, "unknown command"));
  CHECK(test::read_file(scene) == before);
}

TEST_CASE(
    "no output overwrites the checkpoint a run restored, and a last good state takes a name no file of the "
    "run has") {
  const std::string scene = scene_path("bounce_dry");
  const std::string fail = " --quiet --set limits.max_overlap=0.0001 --set 'grains[0].positions=[[0,0,0.00301]]'";
  std::remove("cli_restored.last_good.ckpt");
  std::remove("cli_restored.last_good.1.ckpt");
  REQUIRE(silt_cli("run " + scene + " --steps 1000 --save cli_restored.last_good.ckpt" + fail).code == 0);
  const std::string saved = test::read_file("cli_restored.last_good.ckpt");
  // --stats or --summary onto the checkpoint restored emptied it; the final checkpoint may replace it.
  for (const std::string opt : {"--stats ", "--summary "}) {
    CAPTURE(opt);
    const Result r = silt_cli("run " + scene + " --restore cli_restored.last_good.ckpt --steps 2 " + opt +
                              "cli_restored.last_good.ckpt" + fail);
    CHECK(r.code == 4);
    CHECK(contains(r.out, "it is the checkpoint restored, which it would overwrite"));
    CHECK(test::read_file("cli_restored.last_good.ckpt") == saved);
  }
  // A run restored from NAME.last_good.ckpt that fails again kept its last good state there, over
  // the state it started from.
  const Result again = silt_cli(
      "run " + scene + " --restore cli_restored.last_good.ckpt --steps 2000 --summary cli_restored.json" + fail);
  CHECK(again.code == 3);
  CHECK(contains(again.out, "last good state (step 1451) written to cli_restored.last_good.1.ckpt"));
  CHECK(test::read_file("cli_restored.last_good.ckpt") == saved);
  // Nor does it replace another output named so.
  std::remove("cli_lg.last_good.1.ckpt");
  const Result stats_named =
      silt_cli("run " + scene + " --steps 2000 --summary cli_lg.json --stats cli_lg.last_good.ckpt" + fail);
  CHECK(stats_named.code == 3);
  CHECK(contains(stats_named.out, "written to cli_lg.last_good.1.ckpt"));
  CHECK(test::read_file("cli_lg.last_good.ckpt").rfind("t,", 0) == 0);
}

TEST_CASE("a run refused for an output keeps the VTK files of the run before") {
  // The VTK writer removed the earlier series before the stats path was found unwritable.
  const std::string dir = "cli_vtk_kept";
  std::filesystem::remove_all(dir);
  const std::string run = "run " + scene_path("bounce_dry") + " --steps 10 --quiet --vtk " + dir;
  REQUIRE(silt_cli(run + " --vtk-every 5").code == 0);
  const auto count = [&] {
    return std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator());
  };
  const auto before = count();
  CHECK(before == 7);  // 3 grains and 3 contacts files, index.pvd
  const Result r = silt_cli(run + " --stats cli_no_such_dir/x.csv");
  CHECK(r.code == 4);
  CHECK(contains(r.out, "cannot write stats file 'cli_no_such_dir/x.csv': no directory 'cli_no_such_dir'"));
  CHECK(count() == before);
  std::filesystem::remove_all(dir);
}

TEST_CASE("a control byte in a message is shown escaped, not sent to the terminal") {
  // A file name holding ESC and BEL was echoed raw: the terminal turned red and rang.
  const Result r = silt_cli("run " + scene_path("bounce_dry") + " --restore \"$(printf 'x\\033[31my\\a.ckpt')\"");
  CHECK(r.code == 4);
  CHECK(r.out.find("'x\\x1b[31my\\x07.ckpt'") != std::string::npos);
  CHECK(r.out.find('\033') == std::string::npos);
  CHECK(r.out.find('\a') == std::string::npos);
}
