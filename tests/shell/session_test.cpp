// The shell's session, driven command by command: loading, running, steering, checkpoints,
// background runs and every kind of mistake.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "shell/cli_fixtures.hpp"
#include "shell/shell_fixtures.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::shell;
using test::contains;
using test::Fixture;

TEST_CASE("the shell survives every mistake and keeps the previous scene") {
  Fixture f;
  CHECK_FALSE(f.run("print t"));
  CHECK(f.take_err().find("no scene loaded") != std::string::npos);
  CHECK(f.run("load " + test::scene_path("collision_normal")));
  CHECK_FALSE(f.run("load no_such.toml"));
  CHECK_FALSE(f.run("frobnicate"));
  CHECK_FALSE(f.run("run until"));
  CHECK_FALSE(f.run("run 1.5"));
  CHECK_FALSE(f.run("print tt"));
  CHECK(f.take_err().find("did you mean 't'") != std::string::npos);
  CHECK_FALSE(f.run("set contact.friction -1"));
  CHECK(f.take_err().find("out of range") != std::string::npos);
  CHECK_FALSE(f.run("set contact.frition 0.2"));
  CHECK(f.take_err().find("did you mean 'contact.friction'") != std::string::npos);
  CHECK_FALSE(f.run("restore no_such.ckpt"));
  CHECK_FALSE(f.run("source no_such.silt"));
  f.take_err();
  CHECK_FALSE(f.run("render no_dir/x.png"));
  CHECK(f.take_err().find("cannot write image 'no_dir/x.png': no directory 'no_dir'") != std::string::npos);
  // An empty path, to any command that takes one (`stats ""` said the samples went to a file).
  for (const char* command : {"stats \"\"", "save ''", "frames \"\" every 5", "restore \"\"", "source ''"}) {
    CAPTURE(command);
    CHECK_FALSE(f.run(command));
    CHECK(f.take_err().find("an empty path: give a file or directory") != std::string::npos);
  }
  CHECK_FALSE(f.run("watch t every zero"));
  CHECK_FALSE(f.run("stop"));
  CHECK_FALSE(f.run("run \"unterminated"));
  // Still loaded and working.
  CHECK(f.run("run 10"));
  CHECK(f.value("step") == 10);
}

TEST_CASE("set steers a run: a changed gravity changes the next steps") {
  // Two identical balls in free fall (dt = 1 us); gravity doubled in one after 1000 steps.
  Fixture a, b;
  for (Fixture* f : {&a, &b}) REQUIRE(f->run("load " + test::scene_path("bounce_dry")));
  for (Fixture* f : {&a, &b}) REQUIRE(f->run("run 1000"));
  CHECK(a.hash() == b.hash());
  REQUIRE(b.run("set gravity.magnitude 19.62"));
  CHECK(b.take_out().find("gravity.magnitude = 19.62") != std::string::npos);
  for (Fixture* f : {&a, &b}) REQUIRE(f->run("run 1000"));
  // 1 ms more at the extra 9.81 m/s^2: 9.81e-3 m/s faster.
  CHECK(a.value("p[0].vz") - b.value("p[0].vz") == doctest::Approx(9.81e-3).epsilon(1e-4));
  REQUIRE(b.run("get gravity.magnitude"));
  CHECK(b.take_out().find("19.62") != std::string::npos);
}

TEST_CASE("non-steerable values recompile the scene, keeping the state when the grains are the same") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 100"));
  REQUIRE(f.run("set contact.restitution 0.5"));
  CHECK(f.take_out().find("state kept") != std::string::npos);
  CHECK(f.value("step") == 100);
  REQUIRE(f.run("set grains.0.radius 1.4e-3"));
  CHECK(f.take_out().find("back to t = 0") != std::string::npos);
  CHECK(f.value("step") == 0);
  REQUIRE(f.run("reload"));
  CHECK(f.run("get grains[0].radius"));
  CHECK(f.take_out().find("0.0014") != std::string::npos);  // reload keeps the values set
  // An entry the scene does not have is not "(not set)".
  CHECK_FALSE(f.run("get grains.5.radius"));
  CHECK(f.take_err().find("no grains[5] in the scene") != std::string::npos);
  // A wall moved through a grain of the state kept: refused, the state as it was (it was taken,
  // and the next step failed on the overlap advising stiffer contacts). Clear of it: kept.
  Fixture w;
  REQUIRE(w.run("load " + test::scene_path("bounce_dry")));
  REQUIRE(w.run("run 40000"));  // fallen 7.8 mm: z = 0.0452 m, radius 3 mm
  const std::string before = w.hash();
  CHECK_FALSE(w.run("set walls[0].point [0, 0, 0.047]"));  // clear of where the scene puts it
  CHECK(w.take_err().find("walls[0] at its new place cuts through grain 0") != std::string::npos);
  CHECK(w.hash() == before);
  REQUIRE(w.run("set walls[0].point [0, 0, 0.01]"));
  CHECK(w.take_out().find("state kept") != std::string::npos);
  REQUIRE(w.run("run 10"));
  // A value refused because of another, set before: the refusal names the one typed, then where
  // the check is ("set render.width: ... 9000 x 8193" answered `set render.height 8193`).
  REQUIRE(w.run("set render.width 9000"));
  CHECK_FALSE(w.run("set render.height 8193"));
  CHECK(w.take_err().find("error: column 19: set render.height 8193: refused with the value of an earlier `set "
                          "render.width`: render.width x render.height = 9000 x 8193") != std::string::npos);
  REQUIRE(w.run("set render.height 7000"));     // 63 Mpx
  CHECK_FALSE(w.run("set render.width 9600"));  // refused at the key typed: as it was
  CHECK(w.take_err().find("error: column 18: set render.width: render.width x render.height = 9600 x 7000") !=
        std::string::npos);
}

TEST_CASE("save, restore and reset: a restored run is bitwise the uninterrupted one") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 150"));  // the grains touch from step ~200: the save is before, the end after
  const std::string saved = f.hash();
  REQUIRE(f.run("save session_test.ckpt"));
  REQUIRE(f.run("run 150"));
  const std::string uninterrupted = f.hash();
  REQUIRE(f.run("reset"));
  CHECK(f.value("t") == 0);
  CHECK(f.hash() != saved);
  REQUIRE(f.run("restore session_test.ckpt"));
  CHECK(f.hash() == saved);
  REQUIRE(f.run("run 150"));
  CHECK(f.hash() == uninterrupted);
  // A checkpoint restored is an input: stats and images never overwrite it, a save may.
  const std::string bytes = test::read_file("session_test.ckpt");
  CHECK_FALSE(f.run("stats session_test.ckpt"));
  CHECK(contains(f.take_err(), "it is a checkpoint restored in this session"));
  CHECK_FALSE(f.run("render session_test.ckpt"));
  CHECK(test::read_file("session_test.ckpt") == bytes);
  CHECK(f.run("save session_test.ckpt"));
  std::remove("session_test.ckpt");
}

TEST_CASE("the state after load is the one a run starts from, and saved before the first step it restores") {
  // The shell showed the state before the setup stages: the Taylor-Green field at rest until the
  // first step, a paste without its connections, and a checkpoint saved then was unreadable
  // ("fluid_stat has the wrong length").
  test::TempDir small;
  for (const std::string& scene :
       {test::scene_path("taylor_green_2d"), test::quarter_paste_scene("paste_iso", small.path()),
        test::scene_path("collision_normal")}) {
    CAPTURE(scene);
    Simulation run(compile(load_scene_file(scene)), 1);
    if (run.model().prepare.compress) run.restore(prepare_packing(run.model(), 1));  // paste_iso's
    run.prepare();                                                                   // what `silt run --steps 0` saves
    char expected[17];
    std::snprintf(expected, sizeof expected, "%016llx", static_cast<unsigned long long>(state_hash(run.state())));
    Fixture f;
    test::TempDir dir;
    REQUIRE(f.run("load " + scene));
    CHECK(f.hash() == expected);
    REQUIRE(f.run("save " + dir / "t0.ckpt"));
    REQUIRE(f.run("run 2"));
    const std::string two = f.hash();
    REQUIRE(f.run("reset"));
    CHECK(f.hash() == expected);
    REQUIRE(f.run("restore " + dir / "t0.ckpt"));
    CHECK(f.hash() == expected);
    REQUIRE(f.run("run 2"));
    CHECK(f.hash() == two);
  }
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("taylor_green_2d")));
  CHECK(f.value("fluid.ke") > 0.2);  // (1/4) rho U0^2 L^2 = 0.25 J/m, less the grid's O(h^2)
}

TEST_CASE("restore shows the parameters that differ from the checkpoint's, and refuses directories") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("set contact.friction 0.25"));  // steered, then saved
  REQUIRE(f.run("save session_params.ckpt"));
  REQUIRE(f.run("reload"));
  REQUIRE(f.run("set contact.friction 0.5"));
  f.take_out();
  REQUIRE(f.run("restore session_params.ckpt"));
  const std::string out = f.take_out();
  CHECK(contains(out, "warning: contact.friction = 0.25 in the checkpoint, 0.5 in the scene"));
  CHECK(std::count(out.begin(), out.end(), '\n') == 2);  // the restore line and that one warning
  std::remove("session_params.ckpt");
  CHECK_FALSE(f.run("restore /tmp"));
  CHECK(contains(f.take_err(), "'/tmp' is a directory"));
  CHECK_FALSE(f.run("load /tmp"));
  CHECK(contains(f.take_err(), "'/tmp' is a directory"));
  CHECK_FALSE(f.run("source /tmp"));
  CHECK(contains(f.take_err(), "'/tmp' is a directory"));
  CHECK_FALSE(f.run("save /tmp"));
  CHECK(contains(f.take_err(), "is a directory"));
}

TEST_CASE("run lengths: steps, time, until a condition") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run 0.0001s"));
  CHECK(f.value("step") == 100);
  f.take_out();
  REQUIRE(f.run("run until n_contacts > 0"));
  CHECK(f.take_out().find("condition met") != std::string::npos);
  const double step = f.value("step");
  CHECK(step >= 195);  // the grains meet at t = 0.2 ms
  CHECK(step <= 205);
  CHECK(f.value("n_contacts") == 1);
  REQUIRE(f.run("run until t >= 0.0009"));
  CHECK(f.value("step") == 900);
  // t at the value it shows, whatever the rounding of its sum of steps: holds now, or never.
  REQUIRE(f.run("run until t <= 0.0009 and t == 0.0009"));
  CHECK(f.value("step") == 900);
  CHECK_FALSE(f.run("run until t < 0.0009"));
  CHECK(contains(f.take_err(), "can never hold"));
  CHECK_FALSE(f.run("run until kee > 1"));
  // Lengths past what a step counter holds are refused, not wrapped around.
  CHECK_FALSE(f.run("run 9e18s"));
  CHECK(contains(f.take_err(), "too long"));
  CHECK_FALSE(f.run("watch t every 1e300"));
  CHECK_FALSE(f.run("frames x every 1e300"));
  CHECK_FALSE(f.run("run 1e19"));
  CHECK(f.value("step") == 900);
  // So is a condition that cannot hold before as many steps (`run until t >= 1e300` ran until
  // killed), when its clauses are joined by `and`; with `or` the other clause may end it.
  CHECK_FALSE(f.run("run until t >= 1e300"));
  CHECK(contains(f.take_err(), "cannot hold before 1e+306 steps: too long"));
  CHECK_FALSE(f.run("run until ke >= 0 and step > 1e19"));
  CHECK(contains(f.take_err(), "too long"));
  REQUIRE(f.run("run until t >= 1e300 or step >= 950"));
  CHECK(f.value("step") == 950);
}

TEST_CASE("a background run keeps the prompt, set acts at the next step boundary, stop pauses") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("chute")));
  REQUIRE(f.run("watch t every 100"));
  REQUIRE(f.run("start"));
  CHECK(f.s.running());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  REQUIRE(f.run("set contact.friction 0.2"));  // while running
  CHECK(f.take_out().find("from the next step") != std::string::npos);
  CHECK_FALSE(f.run("set grains[1].count 10"));
  CHECK(f.take_err().find("stop first") != std::string::npos);
  // Several keys need the run stopped, but a value out of its range is said first, at the value.
  CHECK_FALSE(f.run("set contact.friction 0.3 contact.restitution 7"));
  const std::string range = f.take_err();
  CHECK(contains(range, "column 46"));
  CHECK(contains(range, "contact.restitution"));
  CHECK_FALSE(contains(range, "stop first"));
  CHECK_FALSE(f.run("set contact.friction 0.3 contact.restitution 0.5"));  // the chute's law has none
  CHECK(contains(f.take_err(),
                 "column 46: set contact.friction 0.3 contact.restitution 0.5: 'contact.restitution' "
                 "is set but not used"));
  CHECK_FALSE(f.run("set contact.friction 0.3 grains[1].count 10"));
  CHECK(contains(f.take_err(), "set with several keys recompiles the scene: stop first"));
  CHECK_FALSE(f.run("set grains[1].count -1"));  // one key that is not steerable: its range first
  CHECK(contains(f.take_err(), "out of range"));
  CHECK_FALSE(f.run("reset"));
  const double t1 = f.value("t");  // served at a step boundary
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double t2 = f.value("t");
  CHECK(t2 > t1);
  REQUIRE(f.run("save bg_test.ckpt"));
  f.take_out();
  REQUIRE(f.run("stop"));
  CHECK_FALSE(f.s.running());
  // stop prints what the run said: the watch lines (one at least, at its first state) and its end.
  const std::string stopped = f.take_out();
  CHECK(contains(stopped, "step 0:  t = 0\n"));  // the chute is in reduced units
  CHECK(contains(stopped, "paused"));
  CHECK(f.s.take_messages().empty());
  const double t3 = f.value("t");
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  CHECK(f.value("t") == t3);
  REQUIRE(f.run("get contact.friction"));
  CHECK(f.take_out().find("0.2") != std::string::npos);
  std::remove("bg_test.ckpt");
}

TEST_CASE("interrupting a foreground run pauses it at a step boundary") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("chute")));
  std::thread ctrl_c([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    f.s.interrupt();
  });
  REQUIRE(f.run("run 1000000"));
  ctrl_c.join();
  CHECK(f.take_out().find("paused") != std::string::npos);
  const double step = f.value("step");
  CHECK(step > 0);
  CHECK(step < 1000000);
  REQUIRE(f.run("run 5"));  // runs again after a pause
  CHECK(f.value("step") == step + 5);
}

TEST_CASE("help, params, stats, profile, render and frames print what a person reads") {
  Fixture f;
  REQUIRE(f.run("help"));
  CHECK(f.take_out().find("run [N | Ts | until EXPR | until static | until steady]") != std::string::npos);
  REQUIRE(f.run("help watch"));
  CHECK(f.take_out().find("every N steps") != std::string::npos);
  REQUIRE(f.run("load " + test::scene_path("pack_2d")));
  REQUIRE(f.run("params box"));
  const std::string p = f.take_out();
  CHECK(p.find("box.pressure") != std::string::npos);
  CHECK(p.find("N/m") != std::string::npos);  // a 2D pressure: a force per length (it read Pa)
  CHECK(p.find(" Pa ") == std::string::npos);
  REQUIRE(f.run("print pressure"));
  CHECK(contains(f.take_out(), " N/m"));
  REQUIRE(f.run("frames session_frames every 500"));
  REQUIRE(f.run("run 1000"));
  REQUIRE(f.run("frames off"));
  CHECK(f.take_out().find("(3 written)") != std::string::npos);
  REQUIRE(f.run("stats"));
  CHECK(f.take_out().find("phi") != std::string::npos);
  REQUIRE(f.run("profile"));
  CHECK(f.take_out().find("contact_forces") != std::string::npos);
  REQUIRE(f.run("render session_test.png grains chains"));
  CHECK(f.take_out().find("wrote session_test.png") != std::string::npos);
  CHECK_FALSE(f.run("render x.png sparkles"));
  f.take_err();
  CHECK_FALSE(f.run("render x.png []"));  // not the scene's list
  CHECK(f.take_err().find("an empty list draws nothing") != std::string::npos);
  CHECK_FALSE(f.run("set render.draw []"));  // nor as the scene's (every frame was blank)
  CHECK(f.take_err().find("an empty list draws nothing") != std::string::npos);
  // What render.draw refuses for this scene (a dry one: no fluid field, no lubrication), located.
  CHECK_FALSE(f.run("render x.png grains lubrication"));
  CHECK(f.take_err().find("error: column 21: 'lubrication' draws a paste's lubrication forces") != std::string::npos);
  CHECK_FALSE(f.run("render x.png field"));
  CHECK(f.take_err().find("'field' draws a fluid field") != std::string::npos);
  CHECK_FALSE(f.run("render x.jpg"));  // (PNG data under a .jpg name)
  CHECK(f.take_err().find("render writes PNG images") != std::string::npos);
  CHECK_FALSE(std::ifstream("x.jpg").good());
  CHECK_FALSE(std::ifstream("x.png").good());
  std::remove("session_test.png");
  std::system("rm -rf session_frames");
}

TEST_CASE("completion: commands, keys, observables, and file names only for file arguments") {
  Fixture f;
  auto has = [](const std::optional<std::vector<std::string>>& v, const std::string& x) {
    return v && std::find(v->begin(), v->end(), x) != v->end();
  };
  CHECK(has(f.s.complete("", "re"), "reload"));
  CHECK(has(f.s.complete("", "re"), "restore"));
  REQUIRE(f.run("load " + test::scene_path("silo")));
  CHECK(has(f.s.complete("set ", "contact.fr"), "contact.friction"));
  CHECK(has(f.s.complete("set ", "walls[4]"), "walls[4].friction"));
  CHECK(has(f.s.complete("set contact.friction 0.3 ", "walls[4]"), "walls[4].friction"));  // a second pair
  CHECK(has(f.s.complete("print t ", "wall[4].f"), "wall[4].fz"));
  CHECK(has(f.s.complete("help ", "wa"), "watch"));
  CHECK_FALSE(f.s.complete("load ", "sce").has_value());  // files: left to the line editor
  for (const char* line : {"source ", "save ", "restore ", "render ", "frames ", "vtk ", "stats "})
    CHECK_FALSE(f.s.complete(line, "").has_value());
  // Commands without file arguments offer no file names, even with nothing to offer.
  for (const char* line : {"set contact.friction ", "hash ", "reset ", "quit ", "load scene.toml "}) {
    CAPTURE(line);
    const auto none = f.s.complete(line, "sce");
    REQUIRE(none.has_value());
    CHECK(none->empty());
  }
  CHECK(has(f.s.complete("render x.png ", "ch"), "chains"));
  CHECK(has(f.s.complete("frames dir ", ""), "every"));
}

TEST_CASE("a numerical failure stops the run, the shell stays, and the last good state can be saved") {
  std::ofstream("session_soft.toml") << test::kSoftCollision;
  Fixture f;
  REQUIRE(f.run("load session_soft.toml"));
  CHECK_FALSE(f.run("run 1000"));  // the command failed (exit code 3 in a script) ...
  CHECK(f.s.last_error_code() == 3);
  CHECK(contains(f.take_err(), "contact.k_n"));  // ... saying which parameter to change
  CHECK(contains(f.take_out(), "back to the last good state"));
  const double step = f.value("step");
  CHECK(step > 0);
  REQUIRE(f.run("save session_soft.ckpt"));
  REQUIRE(f.run("set contact.k_n 1e5"));  // stiffer: not steerable, recompiled, state kept
  CHECK(f.value("step") == step);
  REQUIRE(f.run("reset"));
  REQUIRE(f.run("run 1000"));
  CHECK(f.take_out().find("done") != std::string::npos);
  CHECK(f.value("step") == 1000);
  std::remove("session_soft.toml");
  std::remove("session_soft.ckpt");
}
