// A module of physics (dem, shear, and later paste, fluid, coupling) as the rest of silt sees it:
// its scene keys with their constraints, its observables, its own State fields and numerical
// events, how it compiles its part of the Model, how it describes it in `silt check`, and which
// parts of it may change while a run goes on. Its stages enter the step through one adder in
// engine/graph/ (DESIGN.md, "Many modules, one step"). The list of modules is in
// engine/graph/modules.cpp: adding a module adds its files and one line there.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "silt/fields.hpp"
#include "silt/grid_field.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"

namespace silt {

namespace graph {
class GraphBuilder;
}

struct ModuleField {
  std::string name;
  Extent extent;
  std::string unit, doc;
};

struct ModuleSpec {
  std::string name;  // "dem", "shear", ...; the prefix of its fields' module column
  std::string doc;   // one line, for `silt check`
  std::vector<KeySpec> keys;
  std::vector<KeyRule> rules;
  std::vector<ObservableSpec> observables;
  std::vector<ModuleField> fields;  // State fields of its own (double arrays)
  std::vector<std::string> events;  // numerical events of its own (silt/events.hpp)
  // Whether a scene turns the module on; empty: always on.
  std::function<bool(const SceneDesc&)> enabled;
  // It acts on grains: on in a scene without them (a fluid alone), a scene error at its table.
  bool needs_grains = false;
  // Its part of compile(), in module order, before the time step is chosen; then, once every
  // module has compiled and the time step is known, `finish`.
  std::function<void(const SceneDesc&, Model&)> compile, finish;
  // Lines for `silt check` ("name   value\n").
  std::function<std::string(const Model&)> describe;
  // Take over the steerable parts of a freshly compiled model (live steering): "" when done,
  // else why the change cannot be made while running (then the model is left as it was).
  std::function<std::string(Model& m, const Model& fresh)> steer;
  // Where a key taken (`set` in the shell) acts not at all in this model, or "": run.dt in a paste,
  // whose step is its own (it replied "from the next step" and changed nothing).
  std::function<std::string(const Model& m, const std::string& key)> inert;
  // What a running model holds that its scene does not say (grains frozen by `freeze`), taken
  // into a model compiled again from the scene (`fresh`) from the running one (`m`).
  std::function<void(Model& fresh, const Model& m)> carry;
  // "" when the module's own fields in a state read from a checkpoint are consistent (their
  // lengths and indices: those of Extent::kFree are not checked otherwise), else what is wrong.
  std::function<std::string(const Model& m, const State& s)> check_state;
  // A note for the run's output after a step (and after the forces of the first state), "" when
  // there is nothing new: something the module handled by a documented choice that the user
  // should know of (a paste's grains with no lubricated connection, held at the affine flow).
  // Read from the state alone, so that it is said once when what it reports changes, and a
  // replayed step (the last good state) says nothing again.
  std::function<std::string(const Model& m, const State& s)> notice;
  // Bytes the module's workspaces will take beyond its fields (a Cholesky factor), for the memory
  // estimate of `silt check` and the refusal of a scene that does not fit.
  std::function<double(const Model& m)> memory_bytes;
  // What the module adds to a run's summary (--summary): one JSON object of numbers under
  // summary_group ("solver" for the paste's linear solves).
  std::string summary_group;
  std::vector<std::string> summary_counts;  // the keys of `summary` that count (written as integers)
  std::function<std::vector<std::pair<std::string, double>>(const Model& m, const State& s)> summary;
  // Its fields on grids (a fluid's velocity, pressure, vorticity at the cell centres), for frames
  // and VTK files: all of them, or (`only` not empty) just the one of that name, which a frame
  // needs; and its line probes, sampled for the summary at the end of a run.
  std::function<std::vector<GridField>(const Model& m, const State& s, std::string_view only)> grid_fields;
  std::function<std::vector<LineSample>(const Model& m, const State& s)> lines;
  // Whether the state is steady by the module's own test (a fluid whose velocity no longer
  // changes), for runs that stop when steady (Model::stop_when_steady, RunEnd::kSteady); empty:
  // the module has no such test.
  std::function<bool(const Model& m, const State& s)> steady;
  // Turn the module off in a copy of the model that compresses the grains dry before the run
  // (procedure O, prepare.compress), restoring what it changed in the DEM's parts.
  std::function<void(Model& dry)> prepare_dry;
  // Whether a state given to a simulation (a packing compressed dry, a checkpoint of a run
  // without this module) has not been started by the module: the stages of the first state then
  // run before its first step, as for a new state (a paste solves the velocities the first drift
  // moves the grains with), or one the module cannot continue as it is under this model (a paste's
  // A state the module has stepped under the same parameters is continued as it is. Empty: never.
  std::function<bool(const Model& m, const State& s)> unstarted;
  // Whether a state the module has started is stale under this model: what the module solved
  // for it depends on parameters changed since (a paste's velocities solved under another
  // viscosity or rate). Such a state, given to a simulation, runs the module's stages of
  // graph::Phase::kResolve before anything is sampled (the same stages a step runs first when the
  // parameters are steered between steps), not the stages of a first state: its forces stay as
  // they are. Empty: never.
  std::function<bool(const Model& m, const State& s)> stale;
  // The parameters its forces on the grains depend on (a contact law's, a drag's viscosity), in a
  // fixed order. The DEM keeps those of every module on with the forces a state holds
  // (dem_forces_under); under a model whose differ (a value steered, or a state given to a model
  // compiled with other values) the forces are made again before the next half kick uses them:
  // the module's stages then run in graph::Phase::kResolve too. Empty: it exerts no such force.
  std::function<std::vector<double>(const Model& m)> force_parameters;
  // Its stages derive state from the grains' forces (a box's stresses): in graph::Phase::kRefresh
  // and kResolve they derive it again from the forces made again.
  bool follows_forces = false;
  // Fills the module's fields of a state made or given (restored) for this model with what a later
  // change must not lose (the cycles' phase origin under the w of this model). Empty: nothing.
  std::function<void(const Model& m, State& s)> adopt;
};

// The stages of a module, added to a step graph (or to the graph that computes the forces of the
// first state; GraphBuilder::phase()).
using StageAdder = std::function<void(graph::GraphBuilder&)>;

struct Module {
  const ModuleSpec* spec = nullptr;
  StageAdder add_stages;
};

// Every module, in order: core, dem, shear, render, then those registered. A module's position
// is the order of its keys, compile step, stages and observables.
const std::vector<Module>& modules();
const Module* find_module(std::string_view name);
// The grid fields (all, or only the one named `only`) and the line probes of every module the
// model enables.
std::vector<GridField> module_grid_fields(const Model& m, const State& s, std::string_view only = {});
std::vector<LineSample> module_lines(const Model& m, const State& s);
// A model compiled again from the scene (`fresh`) with what the running `m` holds beyond its
// scene (ModuleSpec::carry): true when it then describes the same system as `m` (the same
// fingerprint), else `fresh` is left as compiled.
bool carry_running(Model& fresh, const Model& m);
// What the enabled modules say of a key that acts not at all in this model (ModuleSpec::inert), or "".
std::string inert_key_note(const Model& m, const std::string& key);
// Whether a module the model enables has a steady-state test (ModuleSpec::steady).
bool has_steady_test(const Model& m);
// Adds a module after the built-in ones (a module of a test, or of a user's build). Its fields and
// events are registered, and its keys and observables join the schema and the observable table.
// Call before scenes using it are read; not thread-safe.
void register_module(const ModuleSpec* spec, StageAdder add_stages);

}  // namespace silt
