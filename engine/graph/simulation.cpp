// The step loop: graph execution in a task arena of the requested size, numerical checks,
// restart points for the last good state, sampling and stop conditions.
#include "silt/simulation.hpp"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <sstream>

#include "core/parallel.hpp"
#include "core/text.hpp"
#include "dem/stages.hpp"
#include "shear/stages.hpp"
#include "graph/restart_point.hpp"
#include "graph/step_graph.hpp"
#include "silt/observables.hpp"

namespace silt {

struct Simulation::Impl {
  explicit Impl(int threads) : arena(threads) {}
  tbb::task_arena arena;
  std::unique_ptr<graph::StepGraph> graph;
  graph::RestartPoint restart;  // last restart point
  bool primed = false;
};

namespace {

std::string fmt_(double x) { return format_number(x, 4); }


// The key a user changes to stiffen contacts under the scene's law.
std::string stiffness_key(const Model& m) {
  switch (m.contact.law) {
    case NormalLaw::kSpringDashpot: return "contact.contact_time";
    case NormalLaw::kHertz: return "contact.young_modulus";
    default: return "contact.k_n";
  }
}

double kinetic_energy(const State& s) {
  const int D = s.dim, R = s.rot;
  return deterministic_sum(s.n, 4096, [&](int64_t b, int64_t e) {
    double acc = 0;
    for (int64_t i = b; i < e; ++i) {
      if (s.particle_frozen[i]) continue;
      double v2 = 0, w2 = 0;
      for (int k = 0; k < D; ++k) v2 += s.particle_v[D * i + k] * s.particle_v[D * i + k];
      for (int k = 0; k < R; ++k) w2 += s.particle_w[R * i + k] * s.particle_w[R * i + k];
      acc += 0.5 * v2 / s.particle_inv_m[i] + 0.5 * w2 / s.particle_inv_i[i];
    }
    return acc;
  });
}

}  // namespace

Simulation::Simulation(Model model, int threads)
    : model_(std::move(model)),
      state_(make_state(model_)),
      threads_(threads > 0 ? threads : tbb::info::default_concurrency()),
      impl_(std::make_unique<Impl>(threads_)) {
  impl_->arena.execute([&] { impl_->graph = std::make_unique<graph::StepGraph>(model_); });
}

Simulation::~Simulation() = default;

std::vector<std::string> Simulation::stage_names() const {
  std::vector<std::string> out;
  for (const auto& st : impl_->graph->stages()) out.push_back(st.name);
  return out;
}

std::string Simulation::describe_graph() const { return impl_->graph->describe(); }

// Forces of t = 0, so that the first half kick uses them (LAMMPS `setup`). No tangential
// history exists before the first step: the springs stretched by this evaluation are reset.
void Simulation::prepare() {
  if (impl_->primed) return;
  impl_->arena.execute([&] {
    State& s = state_;
    dem::update_neighbors(model_, s);
    dem::contact_forces(model_, s);
    if (!model_.walls.empty()) dem::wall_forces(model_, s);
    dem::add_wall_forces(model_, s);
    if (shear::box_stage_on(model_)) shear::box_stress(model_, s);
    std::fill(s.pair_hist.begin(), s.pair_hist.end(), 0.0);
    std::fill(s.wall_hist.begin(), s.wall_hist.end(), 0.0);
  });
  state_.alarm_overlap.clear();
  state_.alarm_nonfinite.clear();
  impl_->restart.take(state_);
  impl_->primed = true;
}

void Simulation::restore(State s) {
  state_ = adopt_state(model_, std::move(s));
  state_.failure = StepFailure{};
  state_.alarm_overlap.clear();
  state_.alarm_nonfinite.clear();
  impl_->restart.take(state_);
  impl_->primed = true;
}

void Simulation::advance(State& s) {
  s.dt = model_.dt;
  impl_->arena.execute([&] {
    // Up to kSortMin grains every stage is a single block of work (grains are not renumbered in
    // cell order, so the pair schedule is serial too): the flow graph would only add its
    // overhead. Both executors give the same bits.
    if (threads_ == 1 || s.n <= Model::kSortMin)
      impl_->graph->run_serial(model_, s);
    else
      impl_->graph->run_flow(model_, s);
  });
  s.t += s.dt;
  ++s.step;
}

// Numerical checks after a step; fills s.failure and returns false on failure.
bool Simulation::check(State& s) {
  StepFailure& f = s.failure;
  auto fail = [&](const std::string& stage, int64_t particle, const std::string& param, const std::string& msg) {
    f.failed = true;
    f.step = s.step;
    f.stage = stage;
    f.particle = particle;
    f.parameter = param;
    f.message = "step " + std::to_string(s.step) + ", stage " + stage + ": " + msg;
  };
  if (s.alarm_nonfinite.raised()) {
    const int64_t i = s.alarm_nonfinite.first.load();
    if (!f.message.empty() && f.message.rfind("internal error", 0) == 0)
      fail(f.stage, -1, "", f.message);
    else
      fail("kick", s.particle_id[i], "run.dt",
           "grain " + std::to_string(s.particle_id[i]) + " has a non-finite velocity or position; the time step " +
               fmt_(s.dt) + " s is too large for the contacts it meets: reduce run.dt (or run.dt_over_tc)");
    return false;
  }
  if (s.alarm_overlap.raised()) {
    const int64_t i = s.alarm_overlap.first.load();
    const std::string what = "grain " + std::to_string(s.particle_id[i]) + " overlaps a neighbour by " +
                             fmt_(100 * s.alarm_overlap.value.load()) +
                             "% of the smaller radius, beyond limits.max_overlap = " + fmt_(model_.limits.max_overlap);
    const std::string stage = s.n_walls ? "contact_forces/wall_forces" : "contact_forces";
    if (s.dt > model_.dt_stable)
      fail(stage, s.particle_id[i], "run.dt",
           what + ": the time step " + fmt_(s.dt) + " s exceeds the stability limit " + fmt_(model_.dt_stable) +
               " s; reduce run.dt");
    else
      fail(stage, s.particle_id[i], stiffness_key(model_),
           what + ": the contacts are too soft for the loads or the impacts; increase " + stiffness_key(model_) +
               " (stiffer contacts) or reduce the loads");
    return false;
  }
  if (model_.box_control.on) {
    for (int k = 0; k < model_.dim; ++k) {
      const double need = 2 * (2 * model_.r_max + model_.skin);
      if (model_.box_control.controlled[k] && s.box.len[k] < need) {
        fail("box_kick", -1, "box.pressure",
             "the box length along " + std::string(1, "xyz"[k]) + " fell to " + fmt_(s.box.len[k]) +
                 ", below twice the interaction range: use more grains or a lower box.pressure");
        return false;
      }
    }
  }
  if (s.step % model_.limits.check_every == 0) {
    const double ke = impl_->arena.execute([&] { return kinetic_energy(s); });
    const double limit = model_.limits.energy_factor * model_.limits.energy_scale;
    if (!std::isfinite(ke) || ke > limit) {
      fail("energy_check", -1, "run.dt",
           "kinetic energy " + fmt_(ke) + " J exceeds " + fmt_(model_.limits.energy_factor) +
               " times the energy the scene can supply (" + fmt_(model_.limits.energy_scale) +
               " J): the integration is unstable; reduce run.dt (or run.dt_over_tc)");
      return false;
    }
  }
  return true;
}

bool Simulation::step() {
  if (state_.failure.failed) return false;
  prepare();
  advance(state_);
  if (!check(state_)) return false;
  if (state_.step % model_.limits.check_every == 0) impl_->restart.take(state_);
  return true;
}

State Simulation::last_good_state() {
  if (!state_.failure.failed) return state_;
  State s = impl_->restart.give();
  s.boundary_seen = true;
  const int64_t target = state_.failure.step - 1;
  while (s.step < target) advance(s);
  s.alarm_overlap.clear();
  s.alarm_nonfinite.clear();
  return s;
}

bool Simulation::is_static() const {
  const Model& m = model_;
  if (!m.box_control.on) return false;
  const Measurements meas = measure(m, state_);
  const double P = m.box_control.pressure;
  const double a = m.a_max;
  const double force_unit = std::pow(a, m.dim - 1) * P;
  if (meas.max_net_force > m.until_static.force_tol * force_unit) return false;
  for (int k = 0; k < m.dim; ++k)
    if (m.box_control.controlled[k] && std::abs(meas.stress[k][k] / P - 1) > m.until_static.stress_tol) return false;
  // Translational energy only: a rattler spinning in its cage keeps its rotation for ever without
  // touching anything, and it changes no force.
  const int64_t n_free = m.n_grains - m.n_frozen;
  return (meas.ke - meas.ke_rot) / std::max<int64_t>(1, n_free) <= m.until_static.ke_tol * std::pow(a, m.dim) * P;
}

RunReport Simulation::run(const RunOptions& opt) {
  RunReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  auto last_progress = t0;
  prepare();
  auto periodic = [&](bool force) {
    for (const PeriodicHook& h : opt.hooks)
      if (h.every > 0 && h.fn && (force || state_.step % h.every == 0)) h.fn(state_);
  };
  periodic(true);
  // A step stores its pair forces (State::boundary_seen) only when something sees its end: a
  // hook, a request, a restart point or the static test (every check_every steps), the end of
  // the run.
  auto observed = [&](int64_t k) {
    const int64_t next = state_.step + 1;
    if (k + 1 == opt.steps || next % model_.limits.check_every == 0) return true;
    for (const PeriodicHook& h : opt.hooks)
      if (h.every > 0 && h.fn && next % h.every == 0) return true;
    return opt.boundary_wanted && opt.boundary_wanted();
  };
  bool complete = true;  // the state at this boundary holds its pair forces
  for (int64_t k = 0; k < opt.steps; ++k) {
    if (opt.between_steps && complete) opt.between_steps();
    // An interrupt stops at the next complete boundary: at once, or after one more step.
    const bool stop = opt.interrupt && opt.interrupt->load();
    if (stop && complete) {
      rep.end = RunEnd::kInterrupted;
      break;
    }
    state_.boundary_seen = stop || observed(k);
    const bool ok = step();
    complete = state_.boundary_seen;
    state_.boundary_seen = true;
    if (!ok) {
      rep.end = RunEnd::kFailed;
      break;
    }
    ++rep.steps_done;
    periodic(false);
    if (stop) {
      rep.end = RunEnd::kInterrupted;
      break;
    }
    if (opt.stop_when_static && state_.step % model_.limits.check_every == 0 && is_static()) {
      rep.end = RunEnd::kStatic;
      for (const PeriodicHook& h : opt.hooks)
        if (h.every > 0 && h.fn && state_.step % h.every != 0) h.fn(state_);
      break;
    }
    if (opt.on_progress && (k & 63) == 0) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last_progress).count() > 0.2) {
        last_progress = now;
        opt.on_progress(state_);
      }
    }
  }
  rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace silt
