#include "silt/run_job.hpp"

#include <algorithm>
#include <cmath>

namespace silt {
namespace {

std::string stem_of(const std::string& path) {
  const auto dot = path.rfind('.');
  const auto slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path;
  return path.substr(0, dot);
}

}  // namespace

RunJob::RunJob(Simulation& sim, RunJobOptions options) : sim_(sim), o_(std::move(options)) {
  const Model& m = sim_.model();
  if (o_.series) o_.observe = o_.series->names();
  if (o_.observe.empty()) o_.observe = m.observe;
  if (o_.every <= 0) o_.every = m.sample_every;
  observer_.emplace(m, o_.observe);  // throws std::invalid_argument naming a bad observable
  if (!o_.series) stats_.emplace(o_.stats, o_.observe);
  if (!o_.vtk.empty()) vtk_ = std::make_unique<VtkWriter>(o_.vtk);
  if (m.profile.axis >= 0) {
    profile_axis_ = m.profile.axis;
    profile_component_ = m.profile.component;
    profile_slabs_ = m.profile.slabs > 0
                         ? m.profile.slabs
                         : std::clamp(static_cast<int>(sim_.state().box.len[profile_axis_] / m.a_max), 4, 40);
    const char* ax = "xyz";
    const bool sheared = m.shear.on && profile_component_ == 0;
    profiles_.push_back({std::string("v") + ax[profile_component_] + "(" + ax[profile_axis_] + ")",
                         std::string(1, ax[profile_axis_]) + " / L_" + ax[profile_axis_] + " (slab centres); mean " +
                             ax[profile_component_] + " velocity" + (sheared ? " with the shear flow" : "") +
                             ", grains counted in every slab they overlap",
                         {},
                         {}});
  }
}

RunJob::~RunJob() = default;

const char* RunJob::status(RunEnd end) {
  switch (end) {
    case RunEnd::kDone: return "ok";
    case RunEnd::kStatic: return "static";
    case RunEnd::kInterrupted: return "interrupted";
    case RunEnd::kFailed: return "failed";
  }
  return "?";
}

RunReport RunJob::run(RunOptions opt) {
  const Model& m = sim_.model();
  StatsWriter* series = o_.series ? o_.series : &*stats_;
  opt.hooks.push_back(
      {o_.every, [this, series](const State& s) { series->add(observer_->sample(sim_.model(), s), s.t); }});
  if (vtk_)
    opt.hooks.push_back({o_.vtk_every > 0 ? o_.vtk_every : m.sample_every, [this](const State& s) {
                           if (!vtk_error_.empty()) return;
                           try {
                             vtk_->write(sim_.model(), s);
                           } catch (const IoError& e) {
                             vtk_error_ = e.what();
                           }
                         }});
  if (profile_axis_ >= 0)
    opt.hooks.push_back({o_.every, [this](const State& s) {
                           if (s.t < o_.average_from) return;
                           VelocityProfile p =
                               velocity_profile(sim_.model(), s, profile_slabs_, profile_axis_, profile_component_);
                           if (profiles_[0].x.empty()) profiles_[0].x = std::move(p.y);
                           profiles_[0].samples.push_back(std::move(p.vx));
                         }});
  for (const PeriodicHook& h : extra_) opt.hooks.push_back(h);
  const RunReport rep = sim_.run(opt);
  wall_s_ += rep.wall_s;
  steps_ += rep.steps_done;
  return rep;
}

int RunJob::finish(const RunReport& rep) {
  const Model& m = sim_.model();
  int code = 0;
  if (rep.end == RunEnd::kFailed) code = static_cast<int>(ExitCode::kNumerical);
  if (rep.end == RunEnd::kInterrupted) code = 130;
  if (!vtk_error_.empty()) output_errors_.push_back("VTK output stopped (the run went on): " + vtk_error_);
  if (code == 0 && !output_errors_.empty()) code = static_cast<int>(ExitCode::kIo);
  SummaryInput sum;
  sum.scene = o_.scene;
  sum.status = status(rep.end);
  sum.exit_code = code;
  sum.wall_s = wall_s_;
  sum.steps_run = steps_;
  sum.average_from = o_.average_from;
  sum.profiles = profiles_;
  if (m.until_static.on && rep.end == RunEnd::kDone)
    sum.warnings.push_back("run.stop_when_static: no equilibrium within the run length");
  sum.warnings.insert(sum.warnings.end(), warnings_.begin(), warnings_.end());
  sum.warnings.insert(sum.warnings.end(), output_errors_.begin(), output_errors_.end());
  if (stats_) stats_->flush();
  if (rep.end == RunEnd::kFailed) {
    const std::string base = !o_.summary.empty() ? o_.summary : o_.stats;
    if (!base.empty()) {
      last_good_ = stem_of(base) + ".last_good.ckpt";
      write_checkpoint(last_good_, m, sim_.last_good_state());
    }
  }
  if (!o_.summary.empty()) write_summary(o_.summary, sum, sim_, stats());
  if (!o_.save.empty() && rep.end != RunEnd::kFailed) write_checkpoint(o_.save, m, sim_.state());
  return code;
}

}  // namespace silt
