// The step graph: stages per enabled module, the static access check that keeps concurrent stages
// from touching the same field, the run-time check that a stage touches only what it declares,
// loop nodes, and the claim that the graph is the only place where stages are called.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "core/assert.hpp"
#include "dem/stages.hpp"
#include "dem/workspace.hpp"
#include "graph/adders.hpp"
#include "graph/step_graph.hpp"
#include "support/files.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

std::vector<std::string> names(const Model& m, graph::Phase phase = graph::Phase::kStep) {
  Workspaces ws;
  std::vector<std::string> out;
  for (const auto& s : graph::build_stage_list(m, ws, phase).stages) out.push_back(s.name);
  return out;
}

graph::Stage stage(const char* name, std::vector<int> deps, graph::Access reads, graph::Access writes,
                   graph::StageFn fn = nullptr) {
  graph::Stage s;
  s.name = name;
  s.deps = std::move(deps);
  s.why.assign(s.deps.size(), "test");
  s.reads = std::move(reads);
  s.writes = std::move(writes);
  s.fn = std::move(fn);
  return s;
}

}  // namespace

TEST_CASE("stages follow the modules a scene enables") {
  const Model chute = compile(load_scene_file(test::scene_path("chute")));
  CHECK(names(chute) == std::vector<std::string>{"choose_dt", "kick_drift", "update_neighbors", "contact_forces",
                                                 "kick", "energy_check", "advance_clock"});
  const Model silo = compile(load_scene_file(test::scene_path("silo")));
  CHECK(names(silo) == std::vector<std::string>{"choose_dt", "kick_drift", "update_neighbors", "contact_forces",
                                                "wall_forces", "kick", "energy_check", "advance_clock"});
  // A deforming box drifts before the grains and is kicked after them.
  const Model pack = compile(load_scene_file(test::scene_path("pack_2d")));
  CHECK(names(pack) == std::vector<std::string>{"choose_dt", "box_drift", "kick_drift", "update_neighbors",
                                                "contact_forces", "kick", "energy_check", "box_kick", "advance_clock"});
  // The forces of the first state (what Simulation::prepare runs): the same adders.
  CHECK(names(silo, graph::Phase::kSetup) == std::vector<std::string>{"update_neighbors", "keep_springs",
                                                                      "contact_forces", "wall_forces", "sum_forces",
                                                                      "restore_springs", "record_forces_under"});
  // Those forces made again for a state whose parameters were steered, by the same adder: without
  // the neighbour update, when they were made under others.
  // A restored state's contact candidates are chosen first, as update_neighbors chooses them.
  CHECK(names(silo, graph::Phase::kRefresh) ==
        std::vector<std::string>{"forces_stale", "select_candidates", "keep_springs", "contact_forces", "wall_forces",
                                 "sum_forces", "restore_springs", "record_forces_under"});
  CHECK(names(pack, graph::Phase::kSetup).back() == "box_stress");
  CHECK(names(pack, graph::Phase::kRefresh).back() == "box_stress");  // the stresses of the forces made again
}

TEST_CASE("silt check's graph names the module of every stage and why each waits") {
  auto sim = test::simulation_from(test::frictional_gas(3, 0.5, 0.0, 0.0), 1);
  const std::string g = sim->describe_graph();
  CHECK(g.find("contact_forces") != std::string::npos);
  CHECK(g.find("[dem]") != std::string::npos);
  CHECK(g.find("[shear]") != std::string::npos);
  CHECK(g.find("after update_neighbors: iterates the (possibly rebuilt) pair list") != std::string::npos);
}

TEST_CASE("the access check finds stages that may race") {
  std::vector<graph::Stage> st;
  st.push_back(stage("a", {}, {fid::particle_x}, {fid::particle_v}));
  st.push_back(stage("b", {0}, {fid::particle_v}, {fid::particle_f}));
  st.push_back(stage("c", {0}, {fid::particle_f}, {fid::particle_t}));  // reads what b writes, unordered
  CHECK(graph::check_access(st).find("b and c may run at the same time and both use particle_f") != std::string::npos);
  st[2].deps.push_back(1);
  st[2].why.push_back("test");
  CHECK(graph::check_access(st).empty());
  st[0].writes.push_back(fid::particle_t);  // a is before c: no conflict
  CHECK(graph::check_access(st).empty());
}

TEST_CASE("a graph whose dependencies form a cycle is refused") {
  const Model m = compile(load_scene_file(test::scene_path("chute")));
  Workspaces ws;
  graph::GraphBuilder b(m, ws, graph::Phase::kStep);
  const int x = b.add("x", nullptr, {}, {fid::particle_v});
  const int y = b.add("y", nullptr, {}, {fid::particle_x});
  b.after(x, y, "x needs y");
  b.after(y, x, "y needs x");
  CHECK_THROWS_WITH_AS(b.take(), doctest::Contains("cycle"), std::logic_error);
}

TEST_CASE("the run-time access check names a stage that writes or reads an undeclared field") {
  const Model m = compile(load_scene_file(test::scene_path("collision_normal")));
  auto run = [&](graph::Stage st) {
    graph::StageList list;
    list.stages.push_back(std::move(st));
    graph::StepGraph g(std::move(list));
    g.set_access_check(true);
    State s = make_state(m);
    g.run_serial(m, s);
    return s.internal.raised() ? s.internal.message() : std::string();
  };
  // Declares nothing, writes the velocities.
  CHECK(run(stage("sloppy_writer", {}, {}, {}, [](const Model&, State& s) {
          s.particle_v[0] += 1;
        })).find("stage sloppy_writer writes field particle_v") != std::string::npos);
  // Declares the force it writes, but not the positions it reads.
  CHECK(run(stage("sloppy_reader", {}, {}, {fid::particle_f}, [](const Model&, State& s) {
          s.particle_f[0] = 2 * s.particle_x[0];
        })).find("stage sloppy_reader reads field particle_x") != std::string::npos);
  // A stage that writes part of a field reads the rest of it.
  CHECK(run(stage("partial", {}, {}, {fid::particle_f}, [](const Model&, State& s) {
          s.particle_f[0] = 1;
        })).find("reads field particle_f") != std::string::npos);
  // Honest stages pass.
  CHECK(run(stage("honest", {}, {fid::particle_x}, {fid::particle_f}, [](const Model&, State& s) {
          for (size_t k = 0; k < s.particle_f.size(); ++k) s.particle_f[k] = 2 * s.particle_x[k];
        })).empty());
}

TEST_CASE("a broken invariant stops the step with an internal error on both executors") {
  // contact_forces asserts that update_neighbors left it a valid pair list: run it alone on a
  // state that has none.
  const Model m = compile(load_scene_file(test::scene_path("collision_normal")));
  tbb::task_arena arena(2);
  for (bool flow : {false, true}) {
    CAPTURE(flow);
    Workspaces ws;
    auto& w = ws.get<dem::DemWorkspace>();
    graph::StageList list;
    list.stages.push_back(
        stage("contact_forces", {}, {}, {}, [&w](const Model& mm, State& s) { dem::contact_forces(mm, s, w); }));
    State s = make_state(m);
    s.nbr_valid = false;
    arena.execute([&] {
      graph::StepGraph g(std::move(list));
      flow ? g.run_flow(m, s) : g.run_serial(m, s);
      REQUIRE(s.internal.raised());
      CHECK(s.internal.stage() == "contact_forces");
      CHECK(s.internal.message().find("internal error in stage contact_forces") != std::string::npos);
      CHECK(s.internal.message().find("contact_forces.cpp") != std::string::npos);
      CHECK(s.internal.message().find("assertion 'has_pair_list(s)") != std::string::npos);
      CHECK(s.internal.message().find("needs a valid pair list") != std::string::npos);
      CHECK_FALSE(g.diagnose(m, s));
      CHECK(s.failure.internal);
      CHECK(s.failure.stage == "contact_forces");
    });
  }
  // Outside a stage the assertion is an exception of its own type.
  Workspaces ws;
  State s = make_state(m);
  s.nbr_valid = false;
  CHECK_THROWS_AS(dem::contact_forces(m, s, ws.get<dem::DemWorkspace>()), InternalError);
}

TEST_CASE("every stage of the shipped scenes touches only what it declares") {
  for (std::string name :
       {"collision_normal", "bounce_dry", "pack_2d", "silo", "shear2d_dry", "paste_cyclic_alternating"}) {
    CAPTURE(name);
    Model m = compile(load_scene_file(test::scene_path(name)));
    Simulation sim(std::move(m), 1);
    sim.set_access_check(true);
    for (int k = 0; k < 40; ++k) {
      const bool ok = sim.step();
      INFO(sim.state().failure.message);
      REQUIRE(ok);
    }
  }
}

TEST_CASE("the access check changes no result: a checked run gives the bits of an unchecked one") {
  // Each stage of a checked call also runs on poisoned copies of the state; what those runs leave
  // in the modules' workspaces (a factor, a cell list, a renumbering told to the others) must not
  // change what the real run computes.
  for (std::string name : {"pack_2d", "shear2d_dry", "paste_iso", "taylor_green_2d"}) {
    CAPTURE(name);
    auto run = [&](bool check) {
      SceneDesc d = load_scene_file(test::scene_path(name));
      Simulation sim(compile(d), 1);
      sim.set_access_check(check);
      for (int k = 0; k < 130; ++k) {
        const bool ok = sim.step();
        INFO(sim.state().failure.message);
        REQUIRE(ok);
      }
      return state_hash(sim.state());
    };
    CHECK(run(true) == run(false));
  }
}

TEST_CASE("the access check holds in a run whose steps are not all seen, and changes no result") {
  // run() leaves the second half kick of a step whose end nothing sees to the next step's
  // kick_drift (dem::late_kick_drift), which then also reads the force sources (the walls'); with
  // two threads and no walls the pair loop kicks and moves the grains (dem::kick_and_next_drift).
  // The access check runs on the serial executor: small systems run on it at any thread count.
  for (const int threads : {1, 2})
    for (std::string name : {"bounce_dry", "silo", "pack_2d", "collision_normal"}) {
      CAPTURE(name);
      CAPTURE(threads);
      auto run = [&](bool check) {
        Simulation sim(compile(load_scene_file(test::scene_path(name))), threads);
        sim.set_access_check(check);
        RunOptions opt;
        opt.steps = 130;
        opt.hooks.push_back({50, [](const State&) {}});
        const RunReport r = sim.run(opt);
        INFO(sim.state().failure.message);
        REQUIRE(r.end == RunEnd::kDone);
        return state_hash(sim.state());
      };
      CHECK(run(true) == run(false));
    }
}

TEST_CASE("a loop node runs its body M times, on the serial and the flow executor") {
  // The DEM's stages with the clock, four times per run of the node: the same state as four
  // steps of the plain graph.
  const Model m = test::model_from(test::frictional_gas(3, 0.0, 0.0, 0.0));
  tbb::task_arena arena(2);
  for (bool flow : {false, true}) {
    CAPTURE(flow);
    Workspaces ws;
    Simulation plain(m, 1);
    plain.prepare();
    State s = plain.state();
    std::unique_ptr<graph::StepGraph> looped;
    arena.execute([&] {
      graph::GraphBuilder b(m, ws, graph::Phase::kStep);
      b.set_module("test");
      b.loop("dem_cycle", 4, [](graph::GraphBuilder& body) {
        graph::add_core_stages(body);
        graph::add_dem_stages(body);
        body.add_last("advance_clock",
                      [](const Model&, State& st) {
                        st.t += st.dt;
                        ++st.step;
                      },
                      {fid::dt, fid::t, fid::step}, {fid::t, fid::step});
      });
      looped = std::make_unique<graph::StepGraph>(b.take());
    });
    CHECK(looped->describe().find("dem_cycle x 4") != std::string::npos);
    CHECK(looped->stages().size() == 1);
    for (int k = 0; k < 10; ++k) arena.execute([&] { flow ? looped->run_flow(m, s) : looped->run_serial(m, s); });
    for (int k = 0; k < 40; ++k) REQUIRE(plain.step());
    CHECK(s.step == 40);
    CHECK(state_hash(s) == state_hash(plain.state()));
    CHECK(s.profile["kick"].calls == 40);
    CHECK(s.profile["dem_cycle"].calls == 10);
  }
}

namespace {

// The module functions that engine/graph/ makes into stages: those it takes the address of
// (&module::fn) or calls on the model and the state (module::fn(m, s ...), in a stage's lambda).
std::set<std::string> stage_functions() {
  std::set<std::string> names;
  const std::regex pointer(R"(&(dem|shear|paste|fluid|drag)::([a-z_0-9]+))");
  const std::regex call(R"(\b(dem|shear|paste|fluid|drag)::([a-z_0-9]+)\(m+, s\b)");
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(SILT_SOURCE_DIR) / "engine/graph")) {
    if (e.path().extension() != ".cpp") continue;
    const std::string src = test::read_file(e.path());
    for (const std::regex* r : {&pointer, &call})
      for (auto m = std::sregex_iterator(src.begin(), src.end(), *r); m != std::sregex_iterator(); ++m)
        names.insert((*m)[2]);
  }
  return names;
}

}  // namespace

TEST_CASE("the step graph is the only place where stages are called") {
  const std::set<std::string> stages = stage_functions();
  for (const char* s : {"kick_drift", "update_neighbors", "contact_forces", "kick", "box_kick", "box_stress",
                        "lubrication_solve", "paste_dt", "fluid_momentum", "fluid_project", "drag_forces"})
    CHECK(stages.count(s) == 1);
  // No engine source outside engine/graph/ calls one, qualified or not; their definitions aside.
  // Tests and benchmarks may.
  int files = 0;
  for (const auto& e :
       std::filesystem::recursive_directory_iterator(std::filesystem::path(SILT_SOURCE_DIR) / "engine")) {
    if (e.path().extension() != ".cpp" || e.path().parent_path().filename() == "graph") continue;
    ++files;
    const std::string src = test::read_file(e.path());
    for (const std::string& fn : stages) {
      const std::regex call("(^|[^A-Za-z0-9_.>])" + fn + "\\(");
      for (auto m = std::sregex_iterator(src.begin(), src.end(), call); m != std::sregex_iterator(); ++m) {
        const size_t line = src.rfind('\n', static_cast<size_t>(m->position())) + 1;
        const std::string before = src.substr(line, static_cast<size_t>(m->position()) + 1 - line);
        // A definition starts its line with its return type; a call is indented.
        const bool definition = std::regex_match(before, std::regex("[A-Za-z_][A-Za-z0-9_:<>]* "));
        INFO(e.path().string() << " calls the stage " << fn << ": " << before << fn << "(");
        CHECK(definition);
      }
    }
  }
  CHECK(files > 20);
}
