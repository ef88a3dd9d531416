// Building a step: the modules' adders put their stages, with the fields each one reads and
// writes and the reason of each dependency, into a GraphBuilder; it checks that no two stages that
// may run at the same time touch the same field with one of them writing it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/workspace.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::graph {

// kStep: one time step. kSetup: the forces of the first state, so that the first half kick uses
// them (LAMMPS `setup`). kResolve: what modules solve and make again for a state given to a
// simulation, or steered, under changed parameters (ModuleSpec::stale), before its next step: a
// paste's velocities, the forces on the grains; only the adders of modules with a `stale` test or
// forces on the grains (ModuleSpec::force_parameters) are called. kRefresh: the forces alone made
// again, for a state whose parameters were steered (a paste solves its velocities again in the
// step, after the step's own stages); only the adders of modules with forces are called.
enum class Phase { kStep, kSetup, kResolve, kRefresh };

using StageFn = std::function<void(const Model&, State&)>;
using Access = std::vector<FieldId>;

struct StageList;

struct Stage {
  std::string name;
  std::string module;
  StageFn fn;                       // empty for a loop
  std::vector<int> deps;            // stages that must finish first
  std::vector<std::string> why;     // one reason per dependency
  Access reads, writes;             // for a loop, the union of its body's
  std::shared_ptr<StageList> body;  // a loop node: its body, run `times` times per run
  int times = 0;
  // A few scalar operations, no parallel work (choosing dt, advancing the clock): the flow
  // executor runs such stages at the start or the end of a step on its own thread instead of as
  // nodes of the graph, where a hand-over costs more than the stage.
  bool light = false;
  // The stage carries values in its module's workspace to the next stage of the step (the
  // fluid's substeps) or to its own next call (the DEM's candidate travel): it cannot run twice,
  // so the access check checks its writes but not its reads (which it would do by a second run).
  bool carries_workspace = false;
  bool is_loop() const { return body != nullptr; }
};

struct StageList {
  std::vector<Stage> stages;
};

// A module's diagnosis of one of its events raised during a step: fills the failure's stage,
// grain, parameter to change and message (Simulation sets the step and the event).
using DiagnoseFn = std::function<void(const Model&, const State&, const EventSlot&, StepFailure&)>;
struct Diagnosis {
  EventId event;
  DiagnoseFn fn;
};

class GraphBuilder {
 public:
  GraphBuilder(const Model& m, Workspaces& ws, Phase phase);

  const Model& model() const { return *model_; }
  Workspaces& workspaces() { return *ws_; }
  Phase phase() const { return phase_; }
  // The module whose stages are added next (set by build_stage_list for each adder).
  void set_module(std::string name) { module_ = std::move(name); }

  // A stage; returns its index.
  int add(std::string name, StageFn fn, Access reads, Access writes);
  // Mark a stage light (Stage::light).
  void light(int stage) { stages_.at(stage).light = true; }
  // Mark a stage as carrying workspace values to the next (Stage::carries_workspace).
  void carries_workspace(int stage) { stages_.at(stage).carries_workspace = true; }
  // A stage after every stage added so far (the end of a step).
  int add_last(std::string name, StageFn fn, Access reads, Access writes);
  // `stage` runs after `on`; why says what it needs from it ("depends on: ..."). Stages may wait
  // for stages added after them: take() orders them.
  void after(int stage, int on, std::string why);
  // Index of a stage of this graph by name, -1 when there is none.
  int find(std::string_view name) const;
  // A loop node: `body` adds the stages of a sub-graph that the node runs `times` times, one
  // after the other. The node reads and writes what its body does.
  int loop(std::string name, int times, const std::function<void(GraphBuilder&)>& body);

  void diagnose(EventId event, DiagnoseFn fn) { diagnoses_->push_back({event, std::move(fn)}); }
  // A force (and torque) written by stage `writer`, added to the grains by the stages marked
  // with sums_forces(), which then read it and run after `writer`. Its module gives the parameters
  // it depends on (ModuleSpec::force_parameters: the forces are made again when they change), and
  // its stages are then added in Phase::kRefresh too, with no neighbour update before them.
  void add_force(ForceSource source, int writer);
  void sums_forces(int stage);
  // A stage that may add the forces of the step before (dem::late_kick_drift): it reads them, as
  // the writers left them then; it runs before they write this step's.
  void sums_last_forces(int stage);
  const std::shared_ptr<ForceSources>& forces() const { return forces_; }

  // The stages, checked (throws std::logic_error naming two stages that may race).
  StageList take();
  std::vector<Diagnosis> take_diagnoses() { return std::move(*diagnoses_); }

 private:
  GraphBuilder(const GraphBuilder& parent, bool);  // a loop body
  const Model* model_;
  Workspaces* ws_;
  Phase phase_;
  std::string module_;
  std::vector<Stage> stages_;
  std::vector<int> summers_, last_summers_;
  void reads_force(int summer, const ForceSource& source, int writer);
  std::vector<std::pair<ForceSource, int>> force_writers_;  // source, writing stage
  std::shared_ptr<ForceSources> forces_;
  std::shared_ptr<std::vector<Diagnosis>> diagnoses_;
};

// Two stages that the graph may run at the same time must not touch the same field with at least
// one of them writing it. Returns "" or a description of the first conflict.
std::string check_access(const std::vector<Stage>& stages);

// The stages of a Model: every enabled module's adder, in module order, between the core's
// choose_dt and advance_clock (Phase::kStep).
StageList build_stage_list(const Model& m, Workspaces& ws, Phase phase, std::vector<Diagnosis>* diagnoses = nullptr);

// Every field that follows the grains when they are renumbered: what a stage that may renumber
// them writes (and reads), and what the stages that use grain indices must come after.
Access grain_fields();
// a followed by b's fields not already in it.
Access join(Access a, const Access& b);

}  // namespace silt::graph
