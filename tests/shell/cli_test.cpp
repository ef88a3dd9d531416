// The command-line contract (INTERFACE.md): exit codes, messages, output files.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "shell/cli_fixtures.hpp"
#include "shell/shell_fixtures.hpp"
#include "support/scenes.hpp"

using silt::test::read_file;
using silt::test::Result;
using silt::test::silt_cli;
using silt::test::write_file;

TEST_CASE("silt check: a shipped scene, a bad one, a missing one") {
  const Result ok = silt_cli("check " + silt::test::scene_path("collision_normal"));
  CHECK(ok.code == 0);
  CHECK(ok.out.find("dimension    3") != std::string::npos);
  CHECK(ok.out.find("stability limit") != std::string::npos);
  const std::string bad = write_file("cli_bad.toml", "[scene]\ndimension = 3\n[contact]\nmodle = \"hooke\"\n");
  const Result b = silt_cli("check " + bad);
  CHECK(b.code == 2);
  CHECK(b.out.find("cli_bad.toml:4:1: unknown key 'contact.modle'; did you mean 'contact.model'?") !=
        std::string::npos);
  const Result missing = silt_cli("check no_such_scene.toml");
  CHECK(missing.code == 4);
  const Result set = silt_cli("check " + silt::test::scene_path("collision_normal") + " --set contact.restitution=2");
  CHECK(set.code == 2);
  CHECK(set.out.find("--set:1:") != std::string::npos);
  // Scene errors through the binary: a wrong type and an out-of-range value in the file, a time
  // step above the stability limit; each located and exit code 2.
  const std::string typed = write_file("cli_type.toml", "[scene]\ndimension = \"three\"\n");
  const Result ty = silt_cli("check " + typed);
  CHECK(ty.code == 2);
  CHECK(ty.out.find("cli_type.toml:2:13: 'scene.dimension' must be an integer") != std::string::npos);
  const Result range = silt_cli("run " + silt::test::scene_path("collision_normal") + " --set contact.restitution=1.5");
  CHECK(range.code == 2);
  CHECK(range.out.find("out of range (0, 1]") != std::string::npos);
  const Result dt = silt_cli("check " + silt::test::scene_path("chute") + " --set run.dt=0.01");
  CHECK(dt.code == 2);
  CHECK(dt.out.find("stability limit") != std::string::npos);
  CHECK(dt.out.find("run.dt") != std::string::npos);
  CHECK(silt_cli("run").code == 1);
  CHECK(silt_cli("run x.toml --steps abc").code == 1);
  // Numbers that make no sense are usage errors, not silently replaced by defaults.
  for (const char* option : {"--threads 0", "--threads -3", "--every 0", "--steps -5", "--time -1", "--frame-every 0",
                             "--vtk-every 0", "--time 1e300"}) {
    CAPTURE(option);
    CHECK(silt_cli("run " + silt::test::scene_path("collision_normal") + " --quiet " + option).code == 1);
  }
  // An output's interval without the output (it was ignored without a word).
  for (const char* option : {"--frame-every 5", "--vtk-every 5"}) {
    CAPTURE(option);
    const auto r = silt_cli("run " + silt::test::scene_path("collision_normal") + " --quiet --steps 5 " + option);
    CHECK(r.code == 1);
    CHECK(r.out.find("requires") != std::string::npos);
  }
  CHECK(silt_cli("frobnicate").code == 1);
  CHECK(silt_cli("--version").code == 0);
}

TEST_CASE("--every stands for output.every in the frames' and the VTK files' intervals") {
  // (`--every 10` drew one frame where `--set output.every=10` drew eleven)
  const std::string dir = "cli_every_outputs";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directory(dir);
  REQUIRE(silt_cli("run " + silt::test::scene_path("collision_normal") + " --quiet --steps 100 --every 10 --frames " +
                   dir + "/frames --vtk " + dir + "/vtk --set render.width=32 --set render.height=32")
              .code == 0);
  const auto count = [](const std::string& d, const std::string& ext) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(d)) n += e.path().extension() == ext;
    return n;
  };
  CHECK(count(dir + "/frames", ".png") == 11);
  CHECK(count(dir + "/vtk", ".vtu") == 11);
  std::filesystem::remove_all(dir);
}

TEST_CASE("silt run: stats CSV, summary JSON, --observe, --every") {
  const Result r =
      silt_cli("run " + silt::test::scene_path("collision_normal") +
               " --quiet --stats cli_stats.csv --summary cli_summary.json --observe t,ke,p[1].vx --every 50 "
               "--average-from 5e-4 --threads 2");
  CHECK(r.code == 0);
  const std::string csv = read_file("cli_stats.csv");
  CHECK(csv.rfind("t,ke,p[1].vx\n", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 1000 / 50 + 1);
  const auto j = nlohmann::json::parse(read_file("cli_summary.json"));
  CHECK(j["status"] == "ok");
  CHECK(j["exit_code"] == 0);
  CHECK(j["steps"] == 1000);
  CHECK(j["threads"] == 2);
  CHECK(j["n_particles"] == 2);
  CHECK(j["stages"].contains("contact_forces"));
  CHECK(j["observables"]["p[1].vx"]["last"].get<double>() == doctest::Approx(0.4349).epsilon(1e-3));
  CHECK(j["observables"]["t"]["n"] == 11);  // samples with t >= 5e-4
  CHECK(j["average_from"] == 5e-4);
  // --average-from applies whether or not t is among the observables.
  REQUIRE(silt_cli("run " + silt::test::scene_path("collision_normal") +
                   " --quiet --summary cli_summary_ke.json --observe ke --every 50 --average-from 5e-4")
              .code == 0);
  const auto k = nlohmann::json::parse(read_file("cli_summary_ke.json"));
  CHECK(k["observables"]["ke"]["n"] == 11);
  CHECK(silt_cli("run " + silt::test::scene_path("collision_normal") + " --observe t,kee").code == 1);
  CHECK(silt_cli("run " + silt::test::scene_path("collision_normal") + " --stats no_dir/x.csv").code == 4);
  // A scene path that is no UTF-8 (a Latin-1 name) is written with a replacement character: the
  // summary was not written at all.
  write_file("cli_\xe9t\xe9.toml", read_file(silt::test::scene_path("collision_normal")));
  const Result latin = silt_cli("run 'cli_\xe9t\xe9.toml' --quiet --steps 5 --summary cli_latin.json");
  CHECK(latin.code == 0);
  const auto l = nlohmann::json::parse(read_file("cli_latin.json"));
  CHECK(l["scene"].get<std::string>().find("\xef\xbf\xbd") != std::string::npos);
}

TEST_CASE("silt run: a numerical failure exits 3 and keeps the last good state") {
  const std::string scene = write_file("cli_soft.toml", std::string(silt::test::kSoftCollision) + "steps = 1000\n");
  std::remove("cli_fail.last_good.ckpt");
  const Result r = silt_cli("run " + scene + " --quiet --summary cli_fail.json");
  CHECK(r.code == 3);
  CHECK(r.out.find("stage contact_forces") != std::string::npos);
  CHECK(r.out.find("contact.k_n") != std::string::npos);
  CHECK(std::ifstream("cli_fail.last_good.ckpt").good());
  const auto j = nlohmann::json::parse(read_file("cli_fail.json"));
  CHECK(j["status"] == "failed");
  CHECK(j["exit_code"] == 3);
  CHECK(j["failure"]["parameter"] == "contact.k_n");
  // The summary's step and time are the kept state's, the one before the failed step (they were
  // the failed step's while the state kept was the one before it).
  const int64_t failed = j["failure"]["step"];
  CHECK(j["steps"] == failed - 1);
  CHECK(j["steps_run"] == failed - 1);
  const silt::Model m = silt::compile(silt::load_scene_file(scene));
  CHECK(j["sim_time"].get<double>() == doctest::Approx((failed - 1) * m.dt).epsilon(1e-12));
  char t[64];
  std::snprintf(t, sizeof t, "(t = %.6g s)", j["sim_time"].get<double>());
  CHECK(r.out.find(t) != std::string::npos);
}

TEST_CASE("silt run: the last good state is kept without a summary or stats, beside --save or the scene's name") {
  // It was written only beside a summary or stats file: a run with --save alone, or with no
  // output at all, lost it.
  const std::string scene =
      write_file("cli_soft_kept.toml", std::string(silt::test::kSoftCollision) + "steps = 1000\n");
  std::remove("cli_soft_kept.last_good.ckpt");
  CHECK(silt_cli("run " + scene + " --quiet").code == 3);
  CHECK(std::ifstream("cli_soft_kept.last_good.ckpt").good());
  std::remove("cli_kept_save.last_good.ckpt");
  const Result r = silt_cli("run " + scene + " --quiet --save cli_kept_save.ckpt");
  CHECK(r.code == 3);
  CHECK(r.out.find("written to cli_kept_save.last_good.ckpt") != std::string::npos);
  CHECK(std::ifstream("cli_kept_save.last_good.ckpt").good());
  CHECK_FALSE(std::ifstream("cli_kept_save.ckpt").good());  // no final state: the run failed
  // It continues: the last good state restores.
  CHECK(silt_cli("run " + scene + " --quiet --steps 1 --restore cli_kept_save.last_good.ckpt").code == 3);
}

TEST_CASE("silt run: two outputs to one file, or two alternative keys set together, are refused up front") {
  const std::string scene = silt::test::scene_path("collision_normal");
  const Result same = silt_cli("run " + scene + " --steps 5 --stats cli_same.out --summary ./cli_same.out");
  CHECK(same.code == 1);
  CHECK(same.out.find("--stats and --summary name the same file") != std::string::npos);
  CHECK(silt_cli("run " + scene + " --steps 5 --stats cli_same.ckpt --save cli_same.ckpt").code == 1);
  CHECK_FALSE(std::ifstream("cli_same.ckpt").good());
  // A device may take several.
  CHECK(silt_cli("run " + scene + " --quiet --steps 5 --stats /dev/null --summary /dev/null").code == 0);
  // A stats file named as a frame where the frames go was overwritten by that frame.
  const Result frame =
      silt_cli("run " + scene + " --steps 20 --frames cli_frames --frame-every 10 --stats cli_frames/frame_000001.png");
  CHECK(frame.code == 1);
  CHECK(frame.out.find("is a frame's name in --frames") != std::string::npos);
  // So is a checkpoint restored from there, which the frames' directory removed.
  std::filesystem::create_directories("cli_frames");
  REQUIRE(silt_cli("run " + scene + " --quiet --steps 5 --save cli_frames/frame_000000.png").code == 0);
  const Result restored =
      silt_cli("run " + scene + " --steps 5 --restore cli_frames/frame_000000.png --frames cli_frames");
  CHECK(restored.code == 1);
  CHECK(restored.out.find("--restore cli_frames/frame_000000.png is a frame's name in --frames cli_frames, which "
                          "removes it") != std::string::npos);
  CHECK(std::filesystem::exists("cli_frames/frame_000000.png"));
  std::filesystem::remove_all("cli_frames");
  CHECK(silt_cli("run " + scene + " --steps 5 --vtk cli_vtk --summary ./cli_vtk/../cli_vtk/index.pvd").code == 1);
  // A directory not made yet given with its slash.
  std::filesystem::remove_all("cli_slash");
  CHECK(silt_cli("run " + scene + " --steps 20 --frames cli_slash/ --stats cli_slash/frame_000000.png").code == 1);
  // NAME.tmp is a file of its own: a file is written to a temporary file made new beside it
  // (NAME.tmp was, and an output of that name was emptied or refused).
  CHECK(silt_cli("run " + scene + " --quiet --steps 5 --stats cli_tmp.ckpt.tmp --save cli_tmp.ckpt").code == 0);
  CHECK(read_file("cli_tmp.ckpt.tmp").rfind("t,", 0) == 0);
  std::filesystem::remove("cli_tmp.ckpt.tmp");
  std::filesystem::remove("cli_tmp.ckpt");
  // Inside the VTK directory the run makes (it was refused: "no directory").
  std::filesystem::remove_all("cli_vtk");
  CHECK(silt_cli("run " + scene + " --quiet --steps 5 --vtk cli_vtk --summary cli_vtk/summary.json").code == 0);
  CHECK(std::ifstream("cli_vtk/summary.json").good());
  // The last of two alternatives won without a word (channel.toml: a flow rate over a pressure
  // gradient); one --set over the file's alternative still replaces it.
  const std::string channel = silt::test::scene_path("channel");
  const Result both =
      silt_cli("run " + channel + " --steps 2 --set fluid.bulk_velocity=2 --set fluid.pressure_gradient=0");
  CHECK(both.code == 2);
  CHECK(both.out.find("--set:2:") != std::string::npos);
  CHECK(both.out.find("are alternatives") != std::string::npos);
  CHECK(silt_cli("run " + channel + " --quiet --steps 2 --set fluid.pressure_gradient=1").code == 0);
}

TEST_CASE("silt run draws a progress line on a terminal, and none with --quiet or without one") {
  // `script` gives the run a pseudo-terminal; the line is redrawn (\r) a few times per second.
  // 60,000 steps: half a second or more in any build (a redraw comes every 0.2 s at most).
  auto redraws = [](const std::string& steps, const std::string& extra) {
    const std::string cmd = "script -qec '" + silt::test::silt_binary() + " run " + silt::test::scene_path("pack_2d") +
                            " --steps " + steps + " --set run.stop_when_static=false " + extra + "' /dev/null";
    std::FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    pclose(p);
    return std::make_pair(std::count(out.begin(), out.end(), '\r') - std::count(out.begin(), out.end(), '\n'),
                          out.find("step " + steps + "/" + steps + " (100.0%)") != std::string::npos);
  };
  const auto [lines, complete] = redraws("60000", "");
  CHECK(lines >= 2);  // at least one redraw during the run and the final one
  CHECK(complete);
  CHECK(redraws("2000", "--quiet").first <= 0);
  // A fluid without grains counts cell-steps (it showed 0 grain-steps/s).
  const std::string fluid = "script -qec '" + silt::test::silt_binary() + " run " +
                            silt::test::scene_path("taylor_green_2d") + " --steps 20' /dev/null";
  std::FILE* p = popen(fluid.c_str(), "r");
  std::string shown;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) shown.append(buf, n);
  pclose(p);
  CHECK(shown.find("cell-steps/s  eta") != std::string::npos);
  CHECK(shown.find("grain-steps/s") == std::string::npos);
  CHECK(silt_cli("run " + silt::test::scene_path("collision_normal") + " --steps 100").out.find("\r") ==
        std::string::npos);
}

TEST_CASE("the README's parameter table is the schema's") {
  const std::string readme = read_file(std::string(SILT_SOURCE_DIR) + "/README.md");
  const auto begin = readme.find("<!-- params -->\n");
  const auto end = readme.find("<!-- /params -->");
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  const std::string table = readme.substr(begin + 16, end - begin - 16);
  CHECK(table == silt_cli("params --markdown").out);
}

TEST_CASE("silt run --frames writes numbered PNGs and nothing else, and --vtk writes ParaView files") {
  // (its own VTK directory: another case, run at the same time by ctest -j, writes cli_vtk)
  const std::string dir = "cli_frames";
  std::system(("rm -rf " + dir + " cli_frames_vtk").c_str());
  const Result r = silt_cli(
      "run " + silt::test::scene_path("collision_normal") + " --quiet --frames " + dir +
      " --frame-every 250 --vtk cli_frames_vtk --vtk-every 500 --set render.width=200 --set render.height=100");
  CHECK(r.code == 0);
  std::FILE* p = popen(("ls " + dir).c_str(), "r");
  char buf[4096];
  std::string listing(buf, std::fread(buf, 1, sizeof buf, p));
  pclose(p);
  CHECK(listing == "frame_000000.png\nframe_000001.png\nframe_000002.png\nframe_000003.png\nframe_000004.png\n");
  CHECK(std::ifstream("cli_frames_vtk/index.pvd").good());
  CHECK(std::ifstream("cli_frames_vtk/grains_000002.vtu").good());
  CHECK_FALSE(std::ifstream("cli_frames_vtk/grains_000003.vtu").good());
  // A render value that cannot be drawn is a scene error, before the run.
  CHECK(silt_cli("run " + silt::test::scene_path("collision_normal") + " --frames " + dir +
                 " --set render.color_by=temperature")
            .code == 2);
}

TEST_CASE("every shipped scene passes silt check") {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(SILT_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    CAPTURE(entry.path().string());
    const Result r = silt_cli("check " + entry.path().string());
    CHECK(r.code == 0);
    CHECK(r.out.find("\nok") != std::string::npos);
    ++scenes;
  }
  CHECK(scenes >= 7);
}

TEST_CASE("silt run --restore with the scene's length runs on to the scene's end, as the shell's run does") {
  // It ran the scene's whole length again from the checkpoint: 1,000 more steps from step 300 of
  // a run of 1,000.
  const std::string scene = silt::test::scene_path("collision_normal");
  REQUIRE(silt_cli("run " + scene + " --quiet --steps 300 --save cli_restore_300.ckpt").code == 0);
  const Result r = silt_cli("run " + scene + " --quiet --restore cli_restore_300.ckpt --summary cli_restore.json");
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(read_file("cli_restore.json"));
  CHECK(j["steps"] == 1000);
  CHECK(j["steps_run"] == 700);
  CHECK(j["sim_time"].get<double>() == doctest::Approx(1e-3));
  // At the end: nothing left to run, said so (exit 1); --steps goes on.
  REQUIRE(silt_cli("run " + scene + " --quiet --save cli_restore_end.ckpt").code == 0);
  const Result end = silt_cli("run " + scene + " --quiet --restore cli_restore_end.ckpt");
  CHECK(end.code == 1);
  CHECK(end.out.find("the checkpoint is at the scene's end") != std::string::npos);
  CHECK(silt_cli("run " + scene + " --quiet --restore cli_restore_end.ckpt --steps 10").code == 0);
  // A run of a time whose sum of steps rounds a little short of it is at its end too (bounce_dry
  // ends at t = 0.49999999999354 of 0.5 s, and went on by one step).
  const std::string bounce = silt::test::scene_path("bounce_dry");
  REQUIRE(silt_cli("run " + bounce + " --quiet --threads 1 --save cli_restore_bounce.ckpt").code == 0);
  CHECK(silt_cli("run " + bounce + " --quiet --restore cli_restore_bounce.ckpt").code == 1);
  // A length of 0 steps is one (the preparation alone, as --steps 0): it read as none, exit 1.
  const Result none = silt_cli("run " + scene + " --quiet --set run.steps=0 --summary cli_restore_0.json");
  CHECK(none.code == 0);
  CHECK(nlohmann::json::parse(read_file("cli_restore_0.json"))["steps_run"] == 0);
}

TEST_CASE("--steps and --time replace a scene's run length that is too long for its step") {
  // The scene's run.time was checked before --steps replaced it: refused at run.time (exit 2).
  const std::string scene = silt::test::scene_path("collision_normal") + " --quiet --set run.time=1e30";
  CHECK(silt_cli("run " + scene).code == 2);
  const Result steps = silt_cli("run " + scene + " --steps 10 --summary cli_length_steps.json");
  CHECK(steps.code == 0);
  CHECK(nlohmann::json::parse(read_file("cli_length_steps.json"))["steps_run"] == 10);
  const Result time = silt_cli("run " + scene + " --time 1e-5 --summary cli_length_time.json");
  CHECK(time.code == 0);
  CHECK(nlohmann::json::parse(read_file("cli_length_time.json"))["sim_time"].get<double>() == doctest::Approx(1e-5));
  // A --time too long itself is still a usage error.
  CHECK(silt_cli("run " + silt::test::scene_path("collision_normal") + " --quiet --time 1e30").code == 1);
  // The checkpoint records the scene as given, not the run's length: restored under the scene,
  // no parameter differs.
  const std::string plain = silt::test::scene_path("collision_normal") + " --quiet";
  REQUIRE(silt_cli("run " + plain + " --steps 300 --save cli_length.ckpt").code == 0);
  const Result restored = silt_cli("run " + plain + " --restore cli_length.ckpt");
  CHECK(restored.code == 0);
  CHECK(restored.out.find("warning") == std::string::npos);
}

TEST_CASE("a checkpoint restored under a module switched on or off goes on as the shell's kept state does") {
  // `silt run --restore X --set drag.viscosity=V` was refused ("particle_f_drag has 0 entries where
  // 6 are expected", exit 4), and so was the checkpoint of the shell's run with the drag on, under
  // the scene without it; the shell's `restore X`, `set drag.viscosity V` took it.
  const std::string scene = silt::test::scene_path("collision_normal");
  REQUIRE(silt_cli("run " + scene + " --quiet --steps 150 --save cli_module_dry.ckpt").code == 0);
  const Result on = silt_cli("run " + scene +
                             " --quiet --restore cli_module_dry.ckpt --set drag.viscosity=0.01 --steps 100 --save "
                             "cli_module_wet.ckpt --threads 1");
  CHECK(on.code == 0);
  CHECK(on.out.find("drag.viscosity") != std::string::npos);  // the parameter that differs, said
  const std::string script =
      write_file("cli_module.silt", "load " + scene +
                                        "\nrestore cli_module_dry.ckpt\nset drag.viscosity 0.01\nrun 100\nsave "
                                        "cli_module_shell.ckpt\n");
  REQUIRE(silt_cli("play " + script + " --threads 1").code == 0);
  CHECK(read_file("cli_module_wet.ckpt") == read_file("cli_module_shell.ckpt"));
  CHECK(silt_cli("run " + scene + " --quiet --restore cli_module_wet.ckpt --steps 10").code == 0);
}

TEST_CASE("silt play: wait lets a script that starts a run look at its end, the same on any machine") {
  // Without it, a `run` after `start 5` was refused when the background run had not ended yet.
  const std::string script = write_file(
      "play_wait.silt", "load " + silt::test::scene_path("collision_normal") + "\nstart 5\nwait\nrun 10\nprint step\n");
  for (int k = 0; k < 3; ++k) {
    const Result r = silt_cli("play " + script + " --threads 1");
    CHECK(r.code == 0);
    CHECK(r.out.find("step = 15") != std::string::npos);
  }
  const Result none = silt_cli("play " + write_file("play_wait_none.silt", "wait\n"));
  CHECK(none.code == 2);
  CHECK(none.out.find("nothing is running") != std::string::npos);
  // A stop after the wait says the run had ended, as a stop after a run that ended alone does (it
  // failed the script: "nothing is running"); a second stop fails.
  const Result stop =
      silt_cli("play " + write_file("play_wait_stop.silt",
                                    "load " + silt::test::scene_path("collision_normal") + "\nstart 5\nwait\nstop\n"));
  CHECK(stop.code == 0);
  CHECK(stop.out.find("the run had already ended at step 5 (wait)") != std::string::npos);
  const Result twice =
      silt_cli("play " + write_file("play_wait_stop2.silt", "load " + silt::test::scene_path("collision_normal") +
                                                                "\nstart 5\nwait\nstop\nstop\n"));
  CHECK(twice.code == 2);
}

TEST_CASE("silt run: an observable list with an empty name, a name twice or nothing is refused") {
  // '' and ',' fell back to the scene's list, 't,,ke' dropped the empty name, 't,t' wrote t twice,
  // and output.observe = [] wrote blank rows with no header.
  const std::string scene = silt::test::scene_path("collision_normal");
  for (const char* list : {"''", ",", "t,,ke", "t,"}) {
    CAPTURE(list);
    const Result r = silt_cli("run " + scene + " --steps 2 --quiet --observe " + list);
    CHECK(r.code == 1);
    CHECK(r.out.find("has an empty name") != std::string::npos);
  }
  const Result twice = silt_cli("run " + scene + " --steps 2 --quiet --observe t,ke,t");
  CHECK(twice.code == 1);
  CHECK(twice.out.find("'t' is listed twice") != std::string::npos);
  const Result none = silt_cli("run " + scene + " --steps 2 --quiet --set 'output.observe=[]'");
  CHECK(none.code == 2);
  CHECK(none.out.find("an empty list samples nothing") != std::string::npos);
}

TEST_CASE("silt run: an empty path for an output or a checkpoint is a usage error") {
  // ("$OUT" of an unset variable: the run wrote nothing, and an empty --restore began at t = 0)
  const std::string scene = silt::test::scene_path("collision_normal");
  for (const char* option : {"--save", "--summary", "--stats", "--frames", "--vtk", "--restore"}) {
    CAPTURE(option);
    const Result r = silt_cli("run " + scene + " --steps 2 --quiet " + option + " ''");
    CHECK(r.code == 1);
    CHECK(r.out.find(std::string(option) + ": an empty path") != std::string::npos);
  }
}

TEST_CASE("silt play echoes a sourced script's lines as its own, and a binary line without its control bytes") {
  const std::string inner = write_file("play_inner.silt", "print t\n# a comment\nprint step\n");
  const std::string outer =
      write_file("play_outer.silt", "load " + silt::test::scene_path("collision_normal") + "\nsource " + inner + "\n");
  const Result r = silt_cli("play " + outer);
  CHECK(r.code == 0);
  CHECK(r.out.find(inner + ":1> print t") != std::string::npos);
  CHECK(r.out.find(inner + ":3> print step") != std::string::npos);
  CHECK(r.out.find("a comment") == std::string::npos);
  const Result bin = silt_cli("play " + write_file("play_binary.silt", std::string("pr\x1b[2Jint\n")));
  CHECK(bin.code == 2);
  CHECK(bin.out.find('\x1b') == std::string::npos);
}

TEST_CASE("silt with an unknown command names it and the commands there are") {
  const Result r = silt_cli("foo");
  CHECK(r.code == 1);
  CHECK(r.out.find("unknown command 'foo': one of run, check, shell, play, params") != std::string::npos);
}

TEST_CASE("silt check and silt run label no SI unit in reduced units") {
  // The chute (scene.units = "reduced") was described with t_c in s, m* in kg and its run in s.
  const Result c = silt_cli("check " + silt::test::scene_path("chute"));
  REQUIRE(c.code == 0);
  CHECK(c.out.find("33000 steps = 3.3\n") != std::string::npos);
  CHECK(c.out.find(" kg") == std::string::npos);
  // Nor the paste's and the box's lines (pressure 1 Pa, eta = 1 Pa s, box mass in kg, times in s),
  // nor a reduced fluid's (cells in m, rho in kg/m^3).
  for (const char* scene : {"paste_iso", "paste_3d_shear"}) {
    CAPTURE(scene);
    const Result p = silt_cli("check " + silt::test::scene_path(scene));
    REQUIRE(p.code == 0);
    for (const char* unit : {" Pa", " kg", " s,", " s)", " s\n", " m)", " N/m"}) {
      CAPTURE(unit);
      CHECK(p.out.find(unit) == std::string::npos);
    }
  }
  // SI: a 2D pressure is a force per length.
  CHECK(silt_cli("check " + silt::test::scene_path("pack_2d")).out.find("pressure 1 N/m on Lx Ly") !=
        std::string::npos);
  const Result r = silt_cli("run " + silt::test::scene_path("collision_normal") + " --steps 2");
  CHECK(r.out.find("(t = 2e-06 s)") != std::string::npos);  // SI scenes keep theirs
}

TEST_CASE("silt run and check: a --set that is no KEY=VALUE is a usage error, a bad value a scene error") {
  // (a malformed --set exited 2, the code of a scene error)
  const std::string scene = silt::test::scene_path("collision_normal");
  for (const char* cmd : {"run", "check"}) {
    for (const char* set : {"contact.friction", "=0.3"}) {
      CAPTURE(cmd);
      CAPTURE(set);
      const Result r = silt_cli(std::string(cmd) + " " + scene + " --set " + set);
      CHECK(r.code == 1);
      CHECK(r.out.find("expected KEY=VALUE") != std::string::npos);
    }
  }
  const Result bad = silt_cli("run " + scene + " --steps 2 --quiet --set contact.friction=-1");
  CHECK(bad.code == 2);
}

TEST_CASE("a velocity profile leaves slabs with no grain empty, and needs grains") {
  // A slab above a chute's surface read as a measured 0 +- 0; a cavity with no grains gave a
  // profile of zeros.
  REQUIRE(silt_cli("run " + silt::test::scene_path("bounce_dry") +
                   " --quiet --threads 1 --steps 10 --set output.profile_axis=y --set output.profile_slabs=4 "
                   "--summary cli_profile.json")
              .code == 0);
  const auto mean = nlohmann::json::parse(read_file("cli_profile.json"))["profiles"]["vx(y)"]["mean"];
  REQUIRE(mean.size() == 4);
  CHECK(mean[0].is_null());  // the grain, at the centre of y (radius 3 mm of 40 mm), in the middle two
  CHECK(mean[1].is_number());
  CHECK(mean[2].is_number());
  CHECK(mean[3].is_null());
  std::filesystem::remove("cli_profile.json");
  const Result none = silt_cli("check " + silt::test::scene_path("cavity_2d") + " --set output.profile_axis=y");
  CHECK(none.code == 2);
  CHECK(none.out.find("the velocity profile is the grains', and this scene has none") != std::string::npos);
}

TEST_CASE("silt run: an observable with nan samples among the others says why its mean is null") {
  // mu is nan where stress.yy is 0, at t = 0 of a packing: its mean was null with no word.
  const Result r =
      silt_cli("run " + silt::test::scene_path("pack_2d") +
               " --threads 1 --quiet --steps 4000 --every 1000 --observe t,mu --summary cli_nan_mean.json");
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(read_file("cli_nan_mean.json"));
  CHECK(j["observables"]["mu"]["mean"].is_null());
  bool said = false;
  for (const auto& w : j["warnings"]) said |= w.get<std::string>().starts_with("mu: 2 of its 5 samples are nan");
  CHECK(said);
  std::filesystem::remove("cli_nan_mean.json");
}

TEST_CASE("silt run --frames: what a frame could not draw is said once, and in the summary") {
  // A frame too narrow for its colour bar dropped it without a word (the shell's render said it).
  const Result r = silt_cli("run " + silt::test::scene_path("pack_2d") +
                            " --threads 1 --quiet --steps 2000 --frames cli_narrow_frames --frame-every 1000 "
                            "--set render.width=200 --set render.height=300 --summary cli_narrow_frames.json");
  REQUIRE(r.code == 0);
  const std::string said = "silt: warning: frames: a frame 200 px wide has no colour bar (it needs 210 px)";
  CHECK(r.out.find(said) != std::string::npos);
  CHECK(r.out.find(said) == r.out.rfind(said));
  const auto j = nlohmann::json::parse(read_file("cli_narrow_frames.json"));
  CHECK(j["warnings"].dump().find("a frame 200 px wide has no colour bar") != std::string::npos);
  std::filesystem::remove_all("cli_narrow_frames");
  std::filesystem::remove("cli_narrow_frames.json");
}
