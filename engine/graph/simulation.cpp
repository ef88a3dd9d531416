// The step loop: graph execution in a task arena of the requested size, numerical checks,
// restart points for the last good state, sampling and stop conditions.
#include "silt/simulation.hpp"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include "dem/module.hpp"
#include "graph/restart_point.hpp"
#include "graph/step_graph.hpp"
#include "measure/equilibrium.hpp"
#include "silt/module.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt {

struct Simulation::Impl {
  explicit Impl(int threads) : arena(threads) {}
  tbb::task_arena arena;
  Workspaces workspaces;                    // the modules' (graph/graph_builder.hpp)
  std::unique_ptr<graph::StepGraph> step;   // one time step
  std::unique_ptr<graph::StepGraph> setup;  // the forces of the first state
  // What modules solve again for a state given under changed parameters (ModuleSpec::stale).
  std::unique_ptr<graph::StepGraph> resolve;
  // The forces alone made again for a state whose parameters were steered (refresh_steered).
  std::unique_ptr<graph::StepGraph> refresh;
  // The forces the last step left, while a steered change has them made again (refresh_steered).
  std::optional<State> as_stepped;
  bool resolve_pending = false;
  // A parameter steered since the last step (model_for_steering): what it made stale is solved and
  // made again before the next one (ModuleSpec::stale).
  bool steered = false;
  // A state given under other parameters than its solve's, as given, until its first step: a
  // change before that step gives it again under the new parameters (changed back to its own, it
  // is the state given, bit for bit, not a solve of it from the one made under the others).
  std::optional<State> given_stale;
  graph::RestartPoint restart;  // last restart point
  bool primed = false;
  // A new state before its setup stages ran, until its first step: a change of parameters before
  // that step goes back to it, so the setup runs under the new parameters (a run loaded, changed
  // and started is the run compiled with the change, bit for bit).
  std::optional<State> unprepared;
  bool given = false;                // state_given()
  std::vector<std::string> notices;  // the modules' notes not yet taken
};

Simulation::Simulation(Model model, int threads)
    : model_(std::move(model)),
      state_(make_state(model_)),
      threads_(threads > 0 ? threads : tbb::info::default_concurrency()),
      impl_(std::make_unique<Impl>(threads_)) {
  adopt_modules();
  impl_->arena.execute([&] {
    impl_->step = std::make_unique<graph::StepGraph>(model_, impl_->workspaces, graph::Phase::kStep);
    impl_->setup = std::make_unique<graph::StepGraph>(model_, impl_->workspaces, graph::Phase::kSetup);
    impl_->resolve = std::make_unique<graph::StepGraph>(model_, impl_->workspaces, graph::Phase::kResolve);
    impl_->refresh = std::make_unique<graph::StepGraph>(model_, impl_->workspaces, graph::Phase::kRefresh);
  });
}

Simulation::~Simulation() = default;

void Simulation::adopt_modules() {
  for (const Module& mod : modules())
    if (mod.spec->adopt && model_.module_on(mod.spec->name)) mod.spec->adopt(model_, state_);
}

std::vector<std::string> Simulation::stage_names() const {
  std::vector<std::string> out;
  for (const auto& st : impl_->step->stages()) out.push_back(st.name);
  return out;
}

std::string Simulation::describe_graph() const { return impl_->step->describe(); }

Workspaces& Simulation::workspaces() { return impl_->workspaces; }

size_t Simulation::memory_bytes() const {
  return state_bytes(state_) + impl_->restart.bytes() + impl_->workspaces.bytes();
}

double estimated_memory_bytes(const Model& m) {
  double bytes = dem::grains_memory_bytes(m, m.n_grains);
  for (const Module& mod : modules())
    if (mod.spec->memory_bytes && m.module_on(mod.spec->name)) bytes += mod.spec->memory_bytes(m);
  return bytes;
}

void Simulation::set_access_check(bool on) {
  impl_->step->set_access_check(on);
  impl_->setup->set_access_check(on);
  impl_->resolve->set_access_check(on);
  impl_->refresh->set_access_check(on);
}

// Up to kSortMin grains every stage is a single block of work (grains are not renumbered in cell
// order, so the pair schedule is serial too): the flow graph would only add its overhead. Both
// executors give the same bits.
void Simulation::execute(graph::StepGraph& g, State& s) {
  impl_->arena.execute([&] {
    if (threads_ == 1 || s.n <= Model::kSortMin) g.run_serial(model_, s);
    else g.run_flow(model_, s);
  });
}

// The forces of t = 0, so that the first half kick uses them (LAMMPS `setup`): the setup graph
// of the modules' stages. A failure it reports (a paste's first solve) is the first step's.
namespace {
// A module's note as it is kept and told: "step N: " and the note.
std::string notice_prefix(int64_t step) { return "step " + std::to_string(step) + ": "; }
}  // namespace

void Simulation::prepare() {
  if (impl_->primed) {
    refresh_steered();
    resolve_stale();
    return;
  }
  impl_->steered = false;  // (the setup runs under the model as it is now)
  if (state_.step == 0 && !impl_->unprepared) impl_->unprepared = state_;
  state_.events.clear();
  state_.internal.clear();
  execute(*impl_->setup, state_);
  // A failure of the setup is the first step's, as a failed step's: the state it left, and the
  // state before it as the last good one: the unprepared copy of a state at t = 0, else the state
  // restore() was given, which its restart point already holds. (It was dropped, and the first step
  // moved the grains by what the failed solve left: a box through zero named as the failure.)
  const bool ok = impl_->setup->diagnose(model_, state_, state_.step + 1);
  state_.events.clear();
  state_.internal.clear();
  if (ok) impl_->restart.take(state_);
  else if (impl_->unprepared) impl_->restart.take(*impl_->unprepared);
  impl_->primed = true;
  // The notes of this state from an earlier preparation of it (before a steered change, which
  // prepares it again) are superseded: a run printed both, the first of a step since changed.
  const std::string here = notice_prefix(state_.step);
  std::erase_if(impl_->notices, [&](const std::string& n) { return n.starts_with(here); });
  if (ok) collect_notices();
}

namespace {

// The fields `ids` of `from` copied into `to`.
void copy_fields(const State& from, State& to, const std::vector<FieldId>& ids) {
  std::vector<const void*> src(field_infos().size(), nullptr);
  for_each_field(from, [&](const FieldInfo& f, const auto& v) { src[f.id] = &v; });
  for_each_field(to, [&](const FieldInfo& f, auto& v) {
    if (std::find(ids.begin(), ids.end(), f.id) != ids.end())
      v = *static_cast<const std::remove_reference_t<decltype(v)>*>(src[f.id]);
  });
}

}  // namespace

// A parameter steered since the last step that the forces depend on (dem/forces_under.hpp): the
// forces are made again before the next half kick uses them, else the change would enter the
// dynamics half a step late. (A paste's velocities stale under it are solved again by the step
// itself, after the step's own stages, an imposed rate, have run.) Steered back to the parameters
// of the forces the last step left, those forces come back: a value set and set back between two
// steps changes nothing.
void Simulation::refresh_steered() {
  if (!std::exchange(impl_->steered, false) || !forces_stale(state_)) return;
  std::vector<FieldId> made;  // what the forces made again write
  for (const graph::Stage& st : impl_->refresh->stages()) made.insert(made.end(), st.writes.begin(), st.writes.end());
  if (impl_->as_stepped && !forces_stale(*impl_->as_stepped)) {
    copy_fields(*impl_->as_stepped, state_, made);
    impl_->as_stepped.reset();
    impl_->restart.take(state_);
    return;
  }
  if (!impl_->as_stepped) {  // (those fields alone)
    impl_->as_stepped.emplace();
    impl_->as_stepped->module_fields.resize(state_.module_fields.size());
    copy_fields(state_, *impl_->as_stepped, made);
  }
  run_again(*impl_->refresh);
}

// Whether a module that exerts forces on the grains finds them made under other parameters than
// the model's (ModuleSpec::stale: the DEM's record of them, dem/forces_under.hpp).
bool Simulation::forces_stale(const State& s) const {
  for (const Module& mod : modules())
    if (mod.spec->force_parameters && mod.spec->stale && model_.module_on(mod.spec->name) && mod.spec->stale(model_, s))
      return true;
  return false;
}

// A state given under changed parameters: the modules' Phase::kResolve stages, once, before it is
// sampled or stepped. A failure they report is the first step's, as when the same change is
// steered between steps (the state's last good one is the state given).
void Simulation::resolve_stale() {
  if (!impl_->resolve_pending) return;
  impl_->resolve_pending = false;
  run_again(*impl_->resolve);
}

// What a graph of Phase::kResolve or kRefresh makes again for the state as it is. A failure it
// reports is the next step's: the state goes back to its restart point (the state given, or the
// one the change was steered at).
void Simulation::run_again(graph::StepGraph& g) {
  state_.events.clear();
  // (the pair forces made again are stored, as at a boundary seen: State::boundary_seen)
  const bool seen = state_.boundary_seen;
  state_.boundary_seen = true;
  execute(g, state_);
  state_.boundary_seen = seen;
  if (g.diagnose(model_, state_, state_.step + 1)) {
    impl_->restart.take(state_);
    // (what the solve again made is said, as a step's is: a stress left short by a changed h_min)
    collect_notices();
    return;
  }
  // What the failed solve left is not a state to sample: back to the state given, the restart
  // point restore() took of it.
  const StepFailure failure = state_.failure;
  state_ = impl_->restart.give();
  state_.failure = failure;
}

void Simulation::collect_notices() {
  for (const Module& mod : modules()) {
    if (!mod.spec->notice || !model_.module_on(mod.spec->name)) continue;
    std::string note = mod.spec->notice(model_, state_);
    if (note.empty()) continue;
    std::vector<std::string>& v = impl_->notices;
    if (v.size() >= kMaxNotices) v.erase(v.begin());
    v.push_back(notice_prefix(state_.step) + note);
  }
}

std::vector<std::string> Simulation::take_notices() {
  std::vector<std::string> out;
  out.swap(impl_->notices);
  return out;
}

void Simulation::restore(State s) {
  impl_->unprepared.reset();
  impl_->as_stepped.reset();
  impl_->given = true;
  // (as given, before adopt_state: kept when a module finds it stale; only a module that can is on)
  std::optional<State> as_given;
  for (const Module& mod : modules())
    if (mod.spec->stale && model_.module_on(mod.spec->name) && !as_given) as_given = s;
  state_ = adopt_state(model_, std::move(s));
  adopt_modules();
  state_.failure = StepFailure{};
  state_.events.clear();
  state_.internal.clear();
  impl_->workspaces.invalidate();
  impl_->restart.take(state_);
  impl_->primed = true;
  impl_->resolve_pending = false;
  for (const Module& mod : modules()) {
    if (!model_.module_on(mod.spec->name)) continue;
    if (mod.spec->unstarted && mod.spec->unstarted(model_, state_)) impl_->primed = false;
    if (mod.spec->stale && mod.spec->stale(model_, state_)) impl_->resolve_pending = true;
  }
  if (!impl_->primed) impl_->resolve_pending = false;  // the setup solves it as a first state
  impl_->given_stale.reset();
  if (impl_->resolve_pending) impl_->given_stale = std::move(as_given);
}

bool Simulation::state_given() const { return impl_->given; }

const State& Simulation::state_to_carry() const { return impl_->given_stale ? *impl_->given_stale : state_; }

std::string Simulation::kept_state_conflict(const Model& next) const {
  const State& s = state_to_carry();
  for (size_t w = 0; w < next.walls.size() && w < model_.walls.size(); ++w) {
    const Wall& now = next.walls[w];
    const Wall& was = model_.walls[w];
    if (now.point == was.point && now.normal == was.normal) continue;  // (grains may rest on a wall kept)
    for (int64_t i = 0; i < s.n; ++i) {
      if (s.particle_frozen[i]) continue;  // (a frozen grain and a wall exert nothing on each other)
      const double r = s.particle_r[i];
      const double gap = now.gap(s.dim, &s.particle_x[static_cast<size_t>(s.dim * i)], r);
      if (-gap > next.limits.max_overlap * r)
        return "walls[" + std::to_string(w) + "] at its new place cuts through grain " +
               std::to_string(s.particle_id[i]) + " (an overlap of " + format_number(-gap / r * 100, 4) +
               " % of its radius, beyond limits.max_overlap = " + format_number(next.limits.max_overlap * 100, 4) +
               " %): move it clear of the grains, or change it before the first step (or after a reset)";
    }
  }
  return "";
}

Simulation::Recompile Simulation::after_recompile(Model& next) const {
  const Model& m = model();
  if (!carry_running(next, m) || next.walls.size() != m.walls.size()) return Recompile::kGrainsChanged;
  if (next.cells != m.cells || next.box.lo != m.box.lo || next.box.len != m.box.len ||
      next.box.periodic != m.box.periodic)
    return Recompile::kGridChanged;
  return state_.step > 0 || state_given() ? Recompile::kStateKept : Recompile::kStartMadeAgain;
}

Model& Simulation::model_for_steering() {
  if (impl_->unprepared) {
    // Not stepped yet: back to the state before the setup, which the next step (or prepare())
    // runs again under the parameters changed.
    state_ = std::move(*impl_->unprepared);
    impl_->unprepared.reset();
    impl_->workspaces.invalidate();
    impl_->primed = false;
  }
  if (impl_->primed && !state_.failure.failed) impl_->restart.take(state_);
  impl_->steered = true;
  return model_;
}

Simulation::SteerOutcome Simulation::steer_stopped(const Override& change, const SceneDesc* scene) {
  // restore() marks the state given; the last good state is the one we had, given or not (one
  // made from the scene stays so before its first step: a recompile makes it again).
  const bool given = impl_->given;
  if (state_.failure.failed) {
    restore(last_good_state());
    impl_->given = given;
  }
  Model before = model_;
  SteerOutcome out;
  out.cannot = steer(model_for_steering(), change, scene);
  if (out.cannot.empty() && impl_->given_stale) {
    std::optional<State> as_given = std::move(impl_->given_stale);
    restore(std::move(*as_given));
    impl_->given = given;
  }
  prepare();  // before the first step: the setup again, under the change if made
  if (!out.cannot.empty() || !state_.failure.failed) return out;
  // Rather than a state no run can leave: the model and the state as they were.
  out.refused = state_.failure.message;
  model_for_steering() = std::move(before);
  restore(last_good_state());
  impl_->given = given;
  return out;
}

bool Simulation::step() {
  if (state_.failure.failed) return false;
  prepare();
  if (state_.failure.failed) return false;  // (the re-solve of a state given under changed parameters)
  impl_->unprepared.reset();                // (before the step's workspaces are made: never held beside them)
  impl_->given_stale.reset();
  state_.events.clear();
  impl_->as_stepped.reset();
  execute(*impl_->step, state_);
  if (!impl_->step->diagnose(model_, state_)) return false;
  if (state_.step % model_.limits.check_every == 0) impl_->restart.take(state_);
  collect_notices();
  return true;
}

State Simulation::last_good_state() {
  if (!state_.failure.failed) return state_;
  State s = impl_->restart.give();
  s.boundary_seen = true;
  const int64_t target = state_.failure.step - 1;
  // The replay has a state of its own: the workspaces are made anew for it, and again after it.
  impl_->workspaces.invalidate();
  while (s.step < target) execute(*impl_->step, s);
  impl_->workspaces.invalidate();
  s.events.clear();
  s.internal.clear();
  return s;
}

int64_t Simulation::restart_step() const { return impl_->restart.step(); }

bool Simulation::is_static() const {
  const Model& m = model_;
  if (!m.box_control.on) return false;
  const Measurements meas = measure(m, state_, measure_part::kGrains | measure_part::kStress);
  const double P = m.box_control.pressure;
  if (meas.max_net_force > static_force(m)) return false;
  // The stress the contacts carry: with lubrication the box equation holds the total at P at every
  // step, and equilibrium is when the contacts alone carry it (Peyneau 2009 sec. 2.3.2).
  for (int k = 0; k < m.dim; ++k)
    if (m.box_control.controlled[k] &&
        std::abs((meas.stress[k][k] - meas.stress_pairs[k][k]) / P - 1) > m.until_static.stress_tol)
      return false;
  // Translational energy only: a rattler spinning in its cage keeps its rotation for ever without
  // touching anything, and it changes no force.
  // Solved velocities (a paste) carry no kinetic energy of their own: the thesis' criteria are
  // the forces and the stresses (Peyneau 2009 sec. 2.3.2).
  if (m.velocities_solved) return true;
  const int64_t n_free = m.n_grains - m.n_frozen;
  return (meas.ke - meas.ke_rot) / std::max<int64_t>(1, n_free) <= m.until_static.ke_tol * std::pow(m.a_max, m.dim) * P;
}

bool Simulation::is_steady() const {
  bool any = false;
  for (const Module& mod : modules())
    if (mod.spec->steady && model_.module_on(mod.spec->name)) {
      if (!mod.spec->steady(model_, state_)) return false;
      any = true;
    }
  return any;
}

int64_t Simulation::steps_for(const RunOptions& opt) const {
  // The one conversion of a time to steps (the time step is fixed: choose_dt's). An adaptive step
  // runs until the time is reached instead.
  if (opt.time >= 0 && model_.adaptive_dt) return kAdaptiveSteps;
  return opt.time >= 0 ? steps_in(opt.time, model_.dt) : opt.steps;
}

std::string Simulation::long_run_note(const RunOptions& opt) const {
  const int64_t planned = steps_for(opt);
  if (planned <= kLongRunSteps || planned == kAdaptiveSteps) return "";
  return "the run is " + format_number(static_cast<double>(planned), 3) +
         " steps of dt = " + format_number(model_.dt, 4) + model_.unit("s");
}

RunOptions Simulation::scene_run_left() const {
  RunOptions opt;
  opt.steps = 0;
  if (model_.run_time >= 0) {
    // (a run of the scene's time ends 6.5e-12 s short of 0.5 s, by the rounding of its sum of
    // steps: continued from there, it ran one step more)
    const double left = at_or_after(state_.t, model_.run_time) ? 0 : model_.run_time - state_.t;
    if (left > 0 && model_.adaptive_dt) opt.time = left;
    else if (left > 0) opt.steps = steps_in(left, model_.dt);
  } else {
    opt.steps = std::max<int64_t>(0, model_.run_steps - state_.step);
  }
  return opt;
}

void Simulation::within(const std::function<void()>& fn) const { impl_->arena.execute(fn); }

RunReport Simulation::run(const RunOptions& options) {
  RunReport rep;
  RunOptions opt = options;
  // With an adaptive step, a run of a given time stops at the first boundary at or past its end.
  double t_end = -1;
  if (opt.time >= 0) {
    opt.steps = steps_for(opt);
    if (opt.steps < 0)
      throw std::invalid_argument("run of " + format_number(opt.time) + " s: " + too_many_steps(model_.dt));
    if (model_.adaptive_dt) t_end = state_.t + opt.time;
    if (model_.adaptive_dt && opt.time == 0) opt.steps = 0;  // its end is the boundary it starts at
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto last_progress = t0;
  auto done = [&](RunEnd end) {
    rep.end = end;
    rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
  };
  prepare();
  // A state given under changed parameters whose re-solve failed: no sample.
  if (state_.failure.failed) return done(RunEnd::kFailed);
  auto tell = [&] {
    if (impl_->notices.empty()) return;
    for (const std::string& n : take_notices())
      if (opt.on_notice) opt.on_notice(n);
  };
  tell();
  // The hooks' measurements run in the simulation's arena, on its threads and no others.
  auto periodic = [&](bool force) {
    for (const PeriodicHook& h : opt.hooks)
      if (h.every > 0 && h.fn && (force || state_.step % h.every == 0)) within([&] { h.fn(state_); });
  };
  periodic(true);
  // The hooks of the run's last state, which its length did not set (an end in time, at rest).
  auto last_sample = [&] {
    for (const PeriodicHook& h : opt.hooks)
      if (h.every > 0 && h.fn && state_.step % h.every != 0) within([&] { h.fn(state_); });
  };
  // A step stores its pair forces (State::boundary_seen) only when something sees its end: a
  // hook, a request, a restart point or the static and steady tests (every check_every steps),
  // the end of the run.
  auto observed = [&](int64_t k) {
    const int64_t next = state_.step + 1;
    if (k + 1 == opt.steps || next % model_.limits.check_every == 0) return true;
    // A run of a given time with an adaptive step ends at the first boundary at or past it, which
    // no step count foretells: the steps that may end it (within two of the last one's dt) are seen.
    if (t_end >= 0 && state_.t + 2 * state_.dt >= t_end) return true;
    for (const PeriodicHook& h : opt.hooks)
      if (h.every > 0 && h.fn && next % h.every == 0) return true;
    return opt.boundary_wanted && opt.boundary_wanted();
  };
  bool complete = true;  // the state at this boundary holds its pair forces
  // The state a run starts from is tested for equilibrium (a function of the state: `run until
  // static` on a packing at rest ran limits.check_every steps more). The steady test is not: it is
  // the last step's change, which a steered value leaves stale.
  if (opt.stop_when_static && is_static()) return done(RunEnd::kStatic);
  for (int64_t k = 0; k < opt.steps; ++k) {
    if (opt.between_steps && complete) opt.between_steps();
    // An interrupt stops at the next complete boundary: at once, or after one more step.
    const bool stop = opt.interrupt && opt.interrupt->load();
    if (stop && complete) return done(RunEnd::kInterrupted);
    state_.boundary_seen = stop || observed(k);
    const bool ok = step();
    complete = state_.boundary_seen;
    state_.boundary_seen = true;
    if (!ok) return done(RunEnd::kFailed);
    ++rep.steps_done;
    tell();
    periodic(false);
    if (t_end >= 0 && state_.t >= t_end) {
      last_sample();
      break;
    }
    if (stop) return done(RunEnd::kInterrupted);
    // Equilibrium and steady states are tested at the boundaries `observed` makes complete.
    if ((opt.stop_when_static || opt.stop_when_steady) && state_.step % model_.limits.check_every == 0) {
      const RunEnd end = opt.stop_when_static && is_static()   ? RunEnd::kStatic
                         : opt.stop_when_steady && is_steady() ? RunEnd::kSteady
                                                               : RunEnd::kDone;
      if (end != RunEnd::kDone) {
        last_sample();
        return done(end);
      }
    }
    if (opt.on_progress && (k & 63) == 0) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last_progress).count() > 0.2) {
        last_progress = now;
        opt.on_progress(state_);
      }
    }
  }
  return done(RunEnd::kDone);
}

}  // namespace silt
