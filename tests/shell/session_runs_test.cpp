// Runs of a shell session and what goes on around them: requests served at step boundaries while a
// background run ends, runs that end or fail on their own, Ctrl-C in a sourced script, keys that
// replace one another, units.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

#include "shell/shell_fixtures.hpp"
#include "silt/text.hpp"
#include "support/scenes.hpp"

using namespace silt;
using test::contains;
using test::Fixture;

namespace {

void wait_until_stopped(Fixture& f) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (f.s.running() && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  REQUIRE_FALSE(f.s.running());
}

}  // namespace

TEST_CASE("requests made while a background run ends are served once, by the run or after it") {
  // Short background runs, with requests sent as they end: every request gets its answer, and
  // none is left queued for the next run (which would run it again with dangling references: the
  // sanitizer build reports that). Runs that fail also go back to the last good state as they
  // end, a wider window.
  std::ofstream("runs_soft.toml") << test::kSoftCollision;
  for (const char* scene : {"collision_normal", "soft"}) {
    CAPTURE(scene);
    Fixture f;
    REQUIRE(f.run(std::string("load ") + (scene == std::string("soft") ? "runs_soft.toml" : test::scene_path(scene))));
    double last = -1;
    for (int round = 0; round < 60; ++round) {
      REQUIRE(f.run("reset"));
      REQUIRE(f.run("start 40"));
      for (int k = 0; k < 4; ++k) {
        const double step = f.value("step");
        CHECK(step >= 0);
        CHECK(step <= 40);
        CHECK(f.run("set contact.friction 0." + std::to_string(round % 9 + 1)));
        last = step;
      }
      wait_until_stopped(f);
      REQUIRE(f.run("stop"));  // ended by itself: said, not an error
      f.take_out();
    }
    CHECK(last >= 0);
    // The next run starts clean: exactly the steps asked for.
    REQUIRE(f.run("reset"));
    f.s.take_background_failure();
    REQUIRE(f.run("start 5"));
    wait_until_stopped(f);
    CHECK(f.value("step") == 5);
    CHECK(f.take_err().empty());
  }
  std::remove("runs_soft.toml");
}

TEST_CASE("stop after a background run that already ended says so, and its failure is kept for scripts") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("start 10"));
  wait_until_stopped(f);
  REQUIRE(f.run("stop"));
  const std::string out = f.take_out();
  CHECK(contains(out, "done: 10 steps"));
  CHECK(contains(out, "the run had already ended at step 10"));
  CHECK_FALSE(f.run("stop"));  // nothing started since
  CHECK(f.s.take_background_failure().empty());

  std::ofstream("runs_soft2.toml") << test::kSoftCollision;
  REQUIRE(f.run("load runs_soft2.toml"));
  REQUIRE(f.run("start 1000"));
  wait_until_stopped(f);
  CHECK(contains(f.s.take_background_failure(), "contact.k_n"));
  CHECK(f.s.take_background_failure().empty());  // taken once
  const auto messages = f.s.take_messages();
  REQUIRE(!messages.empty());
  CHECK(contains(messages.back(), "failed: "));
  CHECK(contains(messages.back(), "back to the last good state"));
  std::remove("runs_soft2.toml");
}

TEST_CASE("quit during a background run says where it paused it") {
  // (the piped shell left without the line; `silt play` printed it)
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("start 100000000"));
  REQUIRE(f.run("quit"));
  CHECK(contains(f.take_out(), "paused: "));
  CHECK(f.s.take_messages().empty());
}

TEST_CASE("stop after Ctrl-C paused a background run says it was paused, not that it ended") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("chute")));
  REQUIRE(f.run("start 100000000"));
  f.s.interrupt();
  wait_until_stopped(f);
  REQUIRE(f.run("stop"));
  const std::string out = f.take_out();
  CHECK(contains(out, "the run had already been paused (interrupted) at step "));
  CHECK_FALSE(contains(out, "had already ended"));
  // A run that met its `until` ended: it was not paused.
  REQUIRE(f.run("start until step >= " + std::to_string(f.value("step") + 3)));
  wait_until_stopped(f);
  REQUIRE(f.run("stop"));
  const std::string until = f.take_out();
  CHECK(contains(until, "the run had already ended at step "));
  CHECK_FALSE(contains(until, "paused (interrupted)"));
}

TEST_CASE("Ctrl-C during a sourced script pauses the run and abandons the script and those that sourced it") {
  std::ofstream("runs_inner.silt") << "run 100000000\nprint step\n";
  std::ofstream("runs_outer.silt") << "source runs_inner.silt\nprint t\n";
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("chute")));  // before the clock starts: Ctrl-C lands in the run
  f.take_out();
  std::thread ctrl_c([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    f.s.interrupt();
  });
  CHECK_FALSE(f.run("source runs_outer.silt"));
  ctrl_c.join();
  const std::string out = f.take_out(), err = f.take_err();
  CHECK(contains(out, "paused"));
  CHECK_FALSE(contains(out, "\nstep = "));  // the lines after the run were not played
  CHECK_FALSE(contains(out, "\nt = "));
  CHECK(contains(err, "source runs_inner.silt interrupted at line 1"));
  // The next command is not interrupted.
  REQUIRE(f.run("run 3"));
  CHECK(contains(f.take_out(), "done: 3 steps"));
  std::remove("runs_inner.silt");
  std::remove("runs_outer.silt");
}

TEST_CASE("set replaces the keys a value is an alternative to, and errors name what was typed") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));  // gives run.dt_over_tc
  REQUIRE(f.run("set run.dt 2e-7"));
  REQUIRE(f.run("run 1"));  // the state takes the time step at its next step
  CHECK(f.value("dt") == 2e-7);
  REQUIRE(f.run("get run.dt_over_tc"));
  CHECK(contains(f.take_out(), "(not set)"));
  REQUIRE(f.run("set run.dt_over_tc 0.02"));
  REQUIRE(f.run("set scene.seed 5"));  // recompiled from the file and every value set so far
  REQUIRE(f.run("run 1"));
  CHECK(f.value("dt") == doctest::Approx(2e-6));
  REQUIRE(f.run("set gravity.vector [0,0,-1]"));
  REQUIRE(f.run("set gravity.magnitude 2"));
  f.take_out();
  REQUIRE(f.run("reload"));  // with the values set, listed (they were kept without a word)
  CHECK(contains(f.take_out(),
                 "with the value(s) set since it was loaded: run.dt_over_tc = 0.02 scene.seed = 5 "
                 "gravity.magnitude = 2 (load FILE reads the file alone)"));
  REQUIRE(f.run("get gravity.vector"));
  CHECK(contains(f.take_out(), "(not set)"));
  // A value out of range: its key as typed, no made-up file position.
  CHECK_FALSE(f.run("set contact.friction -1"));
  std::string err = f.take_err();
  CHECK(contains(err, "set contact.friction: "));
  CHECK_FALSE(contains(err, "--set"));
  CHECK_FALSE(f.run("set run.dt 1"));  // compiles, but past the stability limit
  err = f.take_err();
  CHECK(contains(err, "set run.dt: "));
  CHECK(contains(err, "stability limit"));
  CHECK_FALSE(contains(err, "--set"));
  // A table where a key is wanted: its keys, not itself as the nearest name.
  CHECK_FALSE(f.run("set gravity [0,0,0]"));
  err = f.take_err();
  CHECK(contains(err, "'gravity' is a table, not a key: its keys are gravity.vector, gravity.magnitude"));
  CHECK_FALSE(contains(err, "did you mean"));
  CHECK_FALSE(f.run("get grains"));
  CHECK(
      contains(f.take_err(), "'grains' is a list of tables, not a key: its keys are grains[K].name, grains[K].count"));
  CHECK_FALSE(f.run("set gravty.vector [0,0,0]"));
  CHECK(contains(f.take_err(), "did you mean 'gravity.vector'?"));
  // fluid.reynolds over the channel's fluid.viscosity: its fluid.dt = 0.01 is then in units of
  // L / U = 2 s, and the step doubled without a word.
  REQUIRE(f.run("load " + test::scene_path("channel")));
  f.take_out();
  // Its Reynolds number is computed from the viscosity the file gives (get answered "(not set)").
  REQUIRE(f.run("get fluid.reynolds"));
  CHECK(f.take_out() == "fluid.reynolds = (not set), computed 20\n");
  REQUIRE(f.run("run 2"));
  f.take_out();
  REQUIRE(f.run("set fluid.reynolds 20"));
  CHECK(contains(f.take_out(), "note: the time step is now 0.02 s (it was 0.01 s), from fluid.dt"));
  REQUIRE(f.run("set fluid.dt 0.005"));  // the step's own key: no note
  CHECK_FALSE(contains(f.take_out(), "note:"));
  // Its unit is then L / U, and the time computed for fluid.dt_max is in it too (it read seconds).
  REQUIRE(f.run("get fluid.dt"));
  CHECK(f.take_out() == "fluid.dt = 0.005 L/U\n");
  REQUIRE(f.run("get fluid.dt_max"));
  CHECK(f.take_out() == "fluid.dt_max = (not set), computed 0.1 L/U\n");
  REQUIRE(f.run("params fluid.dt"));
  CHECK(contains(f.take_out(), "L/U"));
}

TEST_CASE("a string set with quotes, backslashes or blanks is the string typed, and is echoed so") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  f.take_out();
  // (a quote ended the TOML string the value was put in, and a backslash began an escape)
  REQUIRE(f.run("set grains.0.name \"a \\\"b\\\" c:\\\\d\""));
  CHECK(f.take_out() == "grains[0].name = \"a \\\"b\\\" c:\\\\d\" (the state at t = 0 made again)\n");
  REQUIRE(f.run("get grains.0.name"));
  CHECK(f.take_out() == "grains[0].name = \"a \\\"b\\\" c:\\\\d\"\n");
  REQUIRE(f.run("set grains.0.name 5"));  // a word that reads as a number, for a key that takes a string
  f.take_out();
  REQUIRE(f.run("get grains.0.name"));
  CHECK(f.take_out() == "grains[0].name = \"5\"\n");
  // A quoted word for a string key is a TOML string, escapes included, echoed as typed ("42" was
  // echoed as 42, "tab\there" kept its backslash); one TOML refuses is refused.
  REQUIRE(f.run("set grains.0.name \"tab\\there\""));
  CHECK(f.take_out() == "grains[0].name = \"tab\\there\" (the state at t = 0 made again)\n");
  REQUIRE(f.run("get grains.0.name"));
  CHECK(f.take_out() == "grains[0].name = \"tab\\there\"\n");
  REQUIRE(f.run("set grains.0.name '42'"));
  CHECK(f.take_out() == "grains[0].name = '42' (the state at t = 0 made again)\n");
  CHECK_FALSE(f.run("set grains.0.name \"a\\q\""));
  CHECK(contains(f.take_err(), "unknown escape sequence"));
  CHECK_FALSE(f.run("set grains.0.name [1, 2]"));  // a list is not a name
  CHECK(contains(f.take_err(), "must be a string"));
  // A quoted word is a string for any key, as in the scene file and --set (`set output.every
  // "5"` set 5).
  CHECK_FALSE(f.run("set output.every \"5\""));
  CHECK(f.take_err() == "error: column 18: set output.every: 'output.every' must be an integer\n");
  CHECK_FALSE(f.run("set domain.hi '[1, 1, 1]'"));
  CHECK(contains(f.take_err(), "'domain.hi' must be a list of numbers"));
}

TEST_CASE("a value set over the one that replaced its alternatives gives the file's others back, running or not") {
  // `set gravity.vector V` replaces the file's gravity.magnitude and gravity.angle; `set
  // gravity.magnitude G` after it replaced the vector and went on with the angle's default (0, not
  // the file's 30 degrees), until a later recompile read the file again and changed it mid-run.
  test::TempDir dir;
  const std::string scene = dir / "tilted.toml";
  {
    std::ifstream in(test::scene_path("collision_normal"));
    std::ofstream out(scene);
    out << in.rdbuf() << "\n[gravity]\nmagnitude = 9.81\nangle = 30.0\n";
  }
  Fixture once;
  REQUIRE(once.run("load " + scene));
  REQUIRE(once.run("set gravity.magnitude 3"));
  REQUIRE(once.run("run 20"));
  const std::string expected = once.hash();
  for (const bool running : {false, true}) {
    CAPTURE(running);
    Fixture f;
    REQUIRE(f.run("load " + scene));
    REQUIRE(f.run("set gravity.vector [0,0,-2]"));
    if (running) {
      // At a step boundary of a background run: the step it is applied at is not fixed, so the
      // state is compared through the model's gravity, not its hash.
      REQUIRE(f.run("start 1000000"));
      REQUIRE(f.run("set gravity.magnitude 3"));
      REQUIRE(f.run("stop"));
    } else {
      REQUIRE(f.run("set gravity.magnitude 3"));
    }
    f.take_out();
    REQUIRE(f.run("get gravity.angle"));
    CHECK(f.take_out() == "gravity.angle = 30 deg\n");
    REQUIRE(f.run("check"));
    CHECK(contains(f.take_out(), "gravity      (1.5, 0, -2.5981)"));
    if (!running) {
      REQUIRE(f.run("run 20"));
      CHECK(f.hash() == expected);
    }
  }
}

TEST_CASE("a value compile() computes from the one set is said when it changes, and params works on a dry scene") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("cavity_2d")));  // fluid.reynolds = 100
  REQUIRE(f.run("run 10"));
  f.take_out();
  // The lid twice as fast at the same Re: the viscosity doubles (the shell said only the speed).
  REQUIRE(f.run("set fluid.boundary.y_hi_velocity [2.0, 0.0]"));
  const std::string out = f.take_out();
  CHECK(contains(out, "note: fluid.viscosity is now 0.02 Pa s (it was 0.01)"));
  CHECK(contains(out, "note: fluid.velocity_scale is now 2 m/s (it was 1)"));
  // The key set, and those it replaces, are not noted.
  REQUIRE(f.run("set fluid.reynolds 200"));
  CHECK_FALSE(contains(f.take_out(), "fluid.viscosity is now"));
  // `params` with no prefix on a scene without the paste: the paste's computed coarse_ratio read
  // a block the model does not have ("no parameters of this module in the model").
  Fixture dry;
  REQUIRE(dry.run("load " + test::scene_path("collision_normal")));
  REQUIRE(dry.run("params"));
  CHECK(contains(dry.take_out(), "lubrication.coarse_ratio"));
  REQUIRE(dry.run("set contact.friction 0.3"));
  CHECK_FALSE(contains(dry.take_out(), "note:"));
  // A step given in units of the contact time is said to come from that key (it read "from
  // run.dt", which the scene does not give).
  REQUIRE(dry.run("set contact.contact_time 5e-5"));
  CHECK(contains(dry.take_out(), "), from run.dt_over_tc as the scene now reads it"));
}

TEST_CASE("run until samples an observable once however many clauses name it") {
  // It refused "step >= 5 or step >= 10" as "'step' is listed twice".
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("run until step >= 5 or step >= 10"));
  CHECK(f.value("step") == 5);
  REQUIRE(f.run("run until step >= 20 and t > 0 and step >= 12"));
  CHECK(f.value("step") == 20);
  // "and" binds tighter than "or" (it stopped only when both sides of the last "and" held).
  REQUIRE(f.run("run until step >= 25 or t < 0 and dt < 0"));
  CHECK(f.value("step") == 25);
  // A condition t and step can never meet, as they only grow, is refused (it ran without end); one
  // term that can hold is enough.
  for (const char* never :
       {"run until step >= 40 and step < 30", "run until step < 10", "run until t < 0 or step == 3",
        "run until step > 50 and step <= 50", "run until step == 57.5", "run until step > 56 and step < 57"}) {
    CAPTURE(never);
    CHECK_FALSE(f.run(never));
    CHECK(contains(f.take_err(), "the condition can never hold"));
  }
  // It says where t and step are, t to 10 digits (an adaptive step's t typed back as shown to 6,
  // and refused, looked at its value).
  CHECK_FALSE(f.run("run until t < 1e-9"));
  CHECK(contains(f.take_err(), "(now t = " + format_number(f.value("t"), 10) + " s, step 25)"));
  REQUIRE(f.run("run until step < 10 or step >= 30"));
  CHECK(f.value("step") == 30);
  // A step asked exactly beside an observable sampled every 10 steps: tested at every step (it was
  // missed between two tests, and the run went on without end).
  REQUIRE(f.run("run until step == 33 or ke < 0"));
  CHECK(f.value("step") == 33);
  // A window of one step beside an observable sampled every 10 steps (it was missed, and the run
  // went on without end).
  REQUIRE(f.run("run until step > 36 and step < 38 and ke >= 0"));
  CHECK(f.value("step") == 37);
  // A condition that t and step make impossible as the run goes on ends it at the step that does
  // (it ran on past step 45, then to the next test of ke at step 50).
  f.take_out();
  REQUIRE(f.run("run until step == 45 and ke < 0"));
  CHECK(contains(f.take_out(), "the condition can no longer hold (t and step only grow)"));
  CHECK(f.value("step") == 46);
  // An unknown observable is located in the condition.
  CHECK_FALSE(f.run("run until step > 60 or kee < 1"));
  CHECK(contains(f.take_err(), "column 24: unknown observable 'kee'"));
}

TEST_CASE("a field's colour range is said to apply to the field set after it, and refused for a magnitude below 0") {
  // The cavity's render.field_range = [-5, 5] is its vorticity's: |u| drawn on the sequential map
  // from -5 came out one colour.
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("cavity_2d")));
  CHECK_FALSE(f.run("set render.field velocity"));
  CHECK(
      contains(f.take_err(), "render.field_range starts at -5, below 0, where |velocity| (a magnitude, drawn from 0)"));
  REQUIRE(f.run("set render.field pressure"));
  CHECK(contains(f.take_out(),
                 "note: render.field_range = [-5, 5] colours it too (set render.field_range for pressure)"));
  REQUIRE(f.run("set render.field_range [0, 1]"));
  REQUIRE(f.run("set render.field velocity"));
}

TEST_CASE("print, watch and stats show units and sensible digits") {
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("bounce_dry")));
  REQUIRE(f.run("watch t p[0].vz every 500"));
  REQUIRE(f.run("run 1000"));
  const std::string watched = f.take_out();
  CHECK(contains(watched, "step 500:  t = 0.0005 s  p[0].vz = -0.004905 m/s"));
  REQUIRE(f.run("print t step ke p[0].z phi"));
  const std::string printed = f.take_out();
  CHECK(printed.rfind("t      = 0.001 s\nstep   = 1000\nke     = ", 0) == 0);
  CHECK(contains(printed, " J\np[0].z = 0.0529951 m\n"));  // 0.053 - g (1 ms)^2 / 2, six digits
  CHECK(contains(printed, "phi    = 0.000706858\n"));      // dimensionless
  REQUIRE(f.run("stats"));
  const std::string table = f.take_out();
  CHECK(table.rfind("observable  unit", 0) == 0);
  CHECK(contains(table, "p[0].vz     m/s"));
  CHECK(contains(table, "ke          J"));
}

TEST_CASE("run alone goes to the scene's run.time after the step changed, and check gives the new count") {
  // The step count was made at load: after `set run.dt_over_tc 0.02` (half the step) `run` went
  // to twice the scene's time, and `check` said so.
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("collision_normal")));
  REQUIRE(f.run("set run.dt_over_tc 0.02"));
  f.take_out();
  REQUIRE(f.run("check"));
  CHECK(f.take_out().find("500 steps = 0.001 s") != std::string::npos);
  REQUIRE(f.run("run 100"));
  REQUIRE(f.run("set run.dt_over_tc 0.01"));  // the scene's own step again, part-way
  REQUIRE(f.run("run"));
  CHECK(f.value("t") == doctest::Approx(1e-3));
  CHECK(f.value("step") == 100 + 800);
  CHECK_FALSE(f.run("run"));
  CHECK(f.take_err().find("the scene's run length is reached (t = 0.001 s)") != std::string::npos);
}

TEST_CASE("set with several pairs is one change: a fluid's domain and cells valid only together") {
  // A 2:1 cavity could not be reached one key at a time: each alone breaks the equal spacing.
  Fixture f;
  REQUIRE(f.run("load " + test::scene_path("cavity_2d")));
  CHECK_FALSE(f.run("set domain.hi [2.0, 1.0]"));
  CHECK_FALSE(f.run("set fluid.cells [128, 64]"));
  f.take_err();
  REQUIRE(f.run("set domain.hi [2.0, 1.0] fluid.cells [128, 64]"));
  CHECK(contains(f.take_out(), "domain.hi = [2.0, 1.0], fluid.cells = [128, 64] (the domain or the fluid's grid"));
  REQUIRE(f.run("run 2"));
  CHECK(f.value("step") == 2);
  // A refusal names the whole change; a key twice, a key without a value and a run going on are refused.
  CHECK_FALSE(f.run("set fluid.reynolds 200 fluid.cells [129, 64]"));
  CHECK(contains(f.take_err(),  // at the value refused
                 "error: column 36: set fluid.reynolds 200 fluid.cells [129, 64]: the grid spacing must be the same"));
  CHECK(f.run("get fluid.reynolds"));
  CHECK(contains(f.take_out(), "fluid.reynolds = 100"));  // nothing of a refused change is kept
  CHECK_FALSE(f.run("set fluid.reynolds 200 fluid.reynolds 300"));
  CHECK(contains(f.take_err(), "'fluid.reynolds' is given twice"));
  CHECK_FALSE(f.run("set fluid.reynolds 200 fluid.cfl"));
  CHECK(contains(f.take_err(), "'fluid.cfl' has no value"));
  // Two alternatives in one change are refused, as a file giving both is (the last won, unsaid).
  CHECK_FALSE(f.run("set fluid.reynolds 200 fluid.viscosity 0.1"));
  CHECK(contains(f.take_err(), "'fluid.reynolds' and 'fluid.viscosity' are alternatives"));
  // A value in single quotes is one word, as in TOML (it was two).
  REQUIRE(f.run("set scene.name 'a b' run.time 6"));
  REQUIRE(f.run("get scene.name"));
  CHECK(contains(f.take_out(), "scene.name = \"a b\""));
}
