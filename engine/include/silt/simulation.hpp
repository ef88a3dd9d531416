// Simulation: a Model, its State, and the step graph that advances it.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt {

namespace graph {
class StepGraph;
}
class Workspaces;

// How a run ended: its length done, static (Model::until_static), steady (Model::stop_when_steady),
// interrupted, or failed.
enum class RunEnd { kDone, kStatic, kSteady, kInterrupted, kFailed };

// Something to do with the state every `every` steps (samples, frames, VTK files), and at the
// first state of a run; also at the last one when the run stops early on equilibrium.
struct PeriodicHook {
  int64_t every = 0;
  std::function<void(const State&)> fn;
};

struct RunOptions {
  int64_t steps = 0;  // steps to do from the current state
  double time = -1;   // or, when >= 0, simulated time to run [s] (steps_in(time, dt) steps)
  std::vector<PeriodicHook> hooks;
  std::function<void(const State&)> on_progress;  // a few times per second
  // At every step boundary, before the stop checks: where a shell applies steering and serves
  // requests for the state while a run goes on.
  std::function<void()> between_steps;
  // True when between_steps has work for the next boundary (it is then served one step later
  // if the state at this boundary is not complete; see State::boundary_seen).
  std::function<bool()> boundary_wanted;
  // The modules' notes ("step N: ..."; ModuleSpec::notice), as the steps make them.
  std::function<void(const std::string&)> on_notice;
  const std::atomic<bool>* interrupt = nullptr;  // checked at every step boundary
  bool stop_when_static = false;                 // Model::until_static criterion
  bool stop_when_steady = false;                 // the modules' steady-state tests (Model::stop_when_steady)
};

struct RunReport {
  RunEnd end = RunEnd::kDone;
  int64_t steps_done = 0;
  double wall_s = 0;
};

class Simulation {
 public:
  // The step count a run of a given time stands for when the time step is adaptive (it stops on
  // the time instead).
  static constexpr int64_t kAdaptiveSteps = int64_t{1} << 62;
  // threads <= 0: all cores. One thread runs the serial reference executor.
  Simulation(Model model, int threads);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const Model& model() const { return model_; }
  // Between steps only: steerable parameters may be changed through the model returned. The
  // restart point moves to the current state first, so that a replay to the last good state
  // takes the steps before the change with the parameters they were taken with. Before the first
  // step the state goes back to what it was before prepare(), whose setup stages then run again
  // under the changed parameters. After the first step, the forces a changed parameter acts on
  // (ModuleSpec::force_parameters) are made again by the next prepare() (steer_stopped's, or the
  // next step's), so that the next half kick uses the forces of the parameters it steps under.
  Model& model_for_steering();
  // A change steered while stopped (the shell's `set`; a sweep's next point): steer() on the
  // model, then prepare(). A state whose solve failed under an earlier change goes back to its last
  // good one first and is solved again at once under this change (else the next step solves it:
  // its Phase::kResolve stages). If that solve fails, the change is refused with the model and the
  // state as they were.
  struct SteerOutcome {
    std::string cannot;   // steer()'s reason a running model cannot take it (compile the scene again)
    std::string refused;  // the state cannot be solved under the change (a paste's velocities)
  };
  // (`scene`: as steer()'s.)
  SteerOutcome steer_stopped(const Override& change, const SceneDesc* scene = nullptr);
  const State& state() const { return state_; }
  State& state() { return state_; }
  int threads() const { return threads_; }

  // Advance one step. False on a numerical failure; state().failure says why, and
  // last_good_state() gives the state before the failing step.
  bool step();
  // Neighbour lists and forces of the current state (done by the first step if not called).
  void prepare();
  // Continue from a saved state (a checkpoint of this model): its forces, lists and tangential
  // histories are used as they are, so the continuation is bitwise that of the original run.
  void restore(State s);
  // Whether the state was given (restore(): a checkpoint, a prepared packing, a state kept across
  // a recompile) rather than made from the scene: a change of parameters keeps it even before
  // its first step.
  bool state_given() const;
  // The state a recompile carries over (restore() into the new simulation): a state given under
  // other parameters than its solve's as it was given, until its first step (a value set and set
  // back before it is then the state given, bit for bit, as steer_stopped makes it); else state().
  const State& state_to_carry() const;
  // What compiling the scene again with changed values (`next`) does to the state: kept when
  // `next` describes the same grains and walls (with what this model carries beyond its scene,
  // ModuleSpec::carry, which goes into `next`), the same domain and grid, and the state is past
  // its start (a step made, or given); else made again at t = 0, for the reason returned.
  enum class Recompile { kStateKept, kGrainsChanged, kGridChanged, kStartMadeAgain };
  Recompile after_recompile(Model& next) const;
  // Why the state kept by such a recompile cannot go on under `next`: a wall moved into grains,
  // which the next step would find overlapping it beyond limits.max_overlap ("" when none is).
  std::string kept_state_conflict(const Model& next) const;
  RunReport run(const RunOptions& opt);
  // The steps a run of these options does at most: opt.steps, or steps_in(opt.time, dt).
  int64_t steps_for(const RunOptions& opt) const;
  // "the run is N steps of dt = X s" when those are more fixed steps than kLongRunSteps (a contact
  // time of 1e-12 s took 1e11 steps, and wrote 860 MB of stats in its first minute, without a
  // word), else "": said before the run starts.
  std::string long_run_note(const RunOptions& opt) const;
  // What is left of the scene's own run from the current state (a restored one, one part-run in
  // the shell): to its run.time (the time left, with an adaptive step; else that time's steps at
  // the current step), or to its run.steps. Both 0 when the end is reached or the scene gives no
  // length (RunOptions' steps and time: one of them set).
  RunOptions scene_run_left() const;

  // The state after the last step that completed without failure (replayed deterministically
  // from the last restart point, taken every limits.check_every steps).
  State last_good_state();
  // The step of the restart point that replay starts from: at most limits.check_every steps before
  // the current one, so the replay is that short whatever the run's length.
  int64_t restart_step() const;
  // Equilibrium test of Model::until_static on the current state.
  bool is_static() const;
  // The modules' notes made by the steps (and the first state's forces) since the last call,
  // "step N: ..." each; a run hands them to RunOptions::on_notice as they come. At most
  // kMaxNotices are kept between calls (the latest).
  std::vector<std::string> take_notices();
  static constexpr size_t kMaxNotices = 1000;
  // Whether every enabled module with a steady-state test (ModuleSpec::steady) finds the current
  // state steady; false when none has one.
  bool is_steady() const;

  std::vector<std::string> stage_names() const;
  std::string describe_graph() const;
  // Freeze the free grains whose centre is below (or above) `value` along `axis`, between steps:
  // they stop and never move again (a rough base made by a run). The model's grains change with
  // them (a checkpoint saved now belongs to a new system, for [[grains]] frozen_from). Refused
  // (std::invalid_argument) under a deforming box. Returns how many were frozen.
  int64_t freeze(int axis, bool below, double value);
  // The grains flagged in `by_id` (1 by grain id) frozen in the model, as freeze() freezes them,
  // before a checkpoint that froze them is restored (read_checkpoint's `frozen`). Returns how many.
  int64_t freeze_grains(const std::vector<uint8_t>& by_id);
  // Bytes held now: the state, the restart point, the modules' workspaces.
  size_t memory_bytes() const;
  // Runs fn on the simulation's threads and no others (its arena): a measurement made between
  // runs (the shell's print) uses the cores the run was given, as a run's samples do.
  void within(const std::function<void()>& fn) const;
  // The modules' workspaces (core/workspace.hpp), for tests and benchmarks that look inside.
  Workspaces& workspaces();
  // The access check of the serial executor (graph/access_check.hpp), on by default in the
  // sanitizer build.
  void set_access_check(bool on);

 private:
  struct Impl;
  void execute(graph::StepGraph& g, State& s);
  void collect_notices();
  void resolve_stale();
  void refresh_steered();
  bool forces_stale(const State& s) const;
  void run_again(graph::StepGraph& g);
  // ModuleSpec::adopt of every module the model enables, on the state made or restored.
  void adopt_modules();
  Model model_;
  State state_;
  int threads_;
  std::unique_ptr<Impl> impl_;
};

// Bytes a simulation of this model will need, estimated from its field list at a dense packing
// (compile() refuses a scene whose estimate does not fit in the machine).
double estimated_memory_bytes(const Model& m);

// Preparation (Model::prepare): the model of the isotropic compression (no shear, every
// periodic length controlled, until static), and the state it ends in, made ready for `m`:
// time and strain zero, grains at rest, boundary conditions of `m`.
struct PreparationReport {
  RunEnd end = RunEnd::kDone;  // kStatic when the packing reached equilibrium
  bool reached_phi = false;    // prepare.phi: the solid fraction was reached
  int64_t steps = 0;
  double wall_s = 0;
  std::string failure;
  StepFailure failure_detail;      // when end == kFailed
  std::optional<State> last_good;  // when end == kFailed: the compression's last good state (in_compression)
  Profile profile;                 // the compression's wall time per stage (the packing's state starts with none)
  double phi = 0;                  // the solid fraction the compression ended at (before prepare.dilation)
};
Model compression_model(const Model& m);
// The prepared packing: the compression of a fresh state, or of `from`, a compression's state before
// its end (its last good state, in_compression), which it goes on with.
State prepare_packing(const Model& m, int threads, PreparationReport* report = nullptr,
                      const std::atomic<bool>* interrupt = nullptr, const State* from = nullptr);
// Whether the state is a compression's before its end (a preparation's last good state, which a
// restore goes on compressing rather than running the scene from).
bool in_compression(const State& s);
// A state saved under other run parameters (a prepared packing, a checkpoint of the same grains),
// made ready for `m`: its boundary conditions and imposed rates.
State adopt_state(const Model& m, State s);

}  // namespace silt
