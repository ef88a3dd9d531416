#include "silt/run_job.hpp"
#include "silt/module.hpp"
#include "silt/text.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>

namespace silt {
namespace {

std::string stem_of(const std::string& path) {
  const auto dot = path.rfind('.');
  const auto slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path;
  return path.substr(0, dot);
}

// `first`, or when it is a file the run read, another of its outputs or something other than a
// regular file (a directory of that name lost the last good state), NAME.1.ckpt, then .2, ... (NAME
// its name without the extension); "" when a thousand are taken.
std::string free_checkpoint_path(const std::string& first, const RunJobOptions& o,
                                 const std::vector<std::pair<std::string, std::string>>& inputs) {
  if (first.empty()) return "";
  const auto taken = [&](const std::string& path) {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) return true;
    for (const auto& in : inputs)
      if (overwrites(path, in.first)) return true;
    for (const std::string* p : {&o.summary, &o.stats, &o.save})
      if (!output_clash(path, *p).empty()) return true;
    return false;
  };
  for (int k = 0; k < 1000; ++k) {
    const std::string path = k == 0 ? first : stem_of(first) + "." + std::to_string(k) + ".ckpt";
    if (!taken(path)) return path;
  }
  return "";
}

// Where the last good state goes after a failure: NAME.last_good.ckpt beside the summary, else
// beside the stats, else beside the final checkpoint (devices such as /dev/stdout do not count),
// else the fallback. A name that is a file the run read or another of its outputs (a run restored
// from NAME.last_good.ckpt that fails again, stats named so) is numbered instead:
// NAME.last_good.1.ckpt, then .2, ... (free_checkpoint_path).
std::string last_good_path_for(const RunJobOptions& o, const std::vector<std::pair<std::string, std::string>>& inputs) {
  std::string first = o.last_good_fallback;
  for (const std::string* p : {&o.summary, &o.stats, &o.save}) {
    std::error_code ec;
    if (p->empty()) continue;
    const auto st = std::filesystem::status(*p, ec);
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) continue;
    first = stem_of(*p) + ".last_good.ckpt";
    break;
  }
  return free_checkpoint_path(first, o, inputs);
}

// Writes the last good state to `path`; returns whether it could.
bool write_last_good(const std::string& path, const Model& m, const State& s, RunJob& job) {
  if (path.empty()) return false;
  try {
    write_checkpoint(path, m, s);
    return true;
  } catch (const IoError& e) {
    job.add_output_error(e.what());
    return false;
  }
}

}  // namespace

RunJob::RunJob(Simulation& sim, RunJobOptions options) : sim_(sim), o_(std::move(options)) {
  const Model& m = sim_.model();
  if (o_.series) o_.observe = o_.series->names();
  if (o_.observe.empty()) o_.observe = m.observe;
  if (o_.every <= 0) o_.every = m.sample_every;
  observer_.emplace(m, o_.observe);  // throws std::invalid_argument naming a bad observable
  // (the command line refuses them first; a caller of its own, a sweep, would not)
  if (const std::string clash = clashing_outputs(
          {{"the stats file", o_.stats}, {"the summary", o_.summary}, {"the checkpoint", o_.save}}, o_.vtk);
      !clash.empty())
    throw IoError(clash + ": each would overwrite the other");
  // The VTK directory first: the summary or the checkpoint may be named inside it.
  if (!o_.vtk.empty()) make_output_directory(o_.vtk, "VTK");
  check_output_path(o_.stats, "stats file");
  check_output_path(o_.summary, "summary");
  check_output_path(o_.save, "checkpoint", true);
  inputs_ = m.files_read();
  for (const auto& [input, what] : inputs_) {
    check_not_input(o_.summary, input, "summary", what);
    check_not_input(o_.save, input, "checkpoint", what);
    check_not_input(o_.stats, input, "stats file", what);
  }
  // (the final checkpoint may replace the one restored: a run continued in place)
  check_not_input(o_.summary, o_.restored, "summary", "the checkpoint restored");
  check_not_input(o_.stats, o_.restored, "stats file", "the checkpoint restored");
  inputs_.emplace_back(o_.restored, "the checkpoint restored");
  // Every path checked before the VTK writer removes an earlier run's files, and the stats file,
  // which opening truncates, after it: a refused run keeps both.
  if (!o_.vtk.empty()) vtk_ = std::make_unique<VtkWriter>(o_.vtk);
  // A batch run's samples are streamed into their block averages (its memory does not grow).
  if (!o_.series) stats_.emplace(o_.stats, o_.observe, o_.average_from);
}

RunJob::~RunJob() = default;

int64_t RunJob::vtk_removed() const { return vtk_ ? vtk_->removed() : 0; }

void RunJob::add_output_error(std::string e) {
  std::cerr << "silt: " << e << "\n";
  output_errors_.push_back(std::move(e));
}

const char* RunJob::status(RunEnd end) {
  switch (end) {
    case RunEnd::kDone: return "ok";
    case RunEnd::kStatic: return "static";
    case RunEnd::kSteady: return "steady";
    case RunEnd::kInterrupted: return "interrupted";
    case RunEnd::kFailed: return "failed";
  }
  return "?";
}

// One sample of the state, unless the series already holds this step (the end of the shell's
// last run is the start of its next).
void RunJob::sample(const State& s) {
  StatsWriter& series = o_.series ? *o_.series : *stats_;
  if (series.last_step() == s.step && series.samples() > 0) return;
  series.add(observer_->sample(sim_.model(), s), s.t, s.step);
}

RunReport RunJob::run(RunOptions opt) {
  const Model& m = sim_.model();
  // The velocity profile, its slabs set at the start of the run (a prepared box has its own size).
  if (m.profile.axis >= 0 && profiles_.empty()) {
    profile_axis_ = m.profile.axis;
    profile_component_ = m.profile.component;
    // Clamped as a double: the box may be far larger than an int counts (a NaN gives 4).
    const double fit = sim_.state().box.len[profile_axis_] / m.a_max;
    profile_slabs_ = m.profile.slabs > 0 ? m.profile.slabs
                                         : (fit >= 40.0  ? 40
                                            : fit >= 4.0 ? static_cast<int>(fit)
                                                         : 4);
    const char* ax = "xyz";
    const bool sheared = m.shear.on && profile_component_ == 0;
    profiles_.push_back({std::string("v") + ax[profile_component_] + "(" + ax[profile_axis_] + ")",
                         std::string(1, ax[profile_axis_]) + " / L_" + ax[profile_axis_] + " (slab centres); mean " +
                             ax[profile_component_] + " velocity" + (sheared ? " with the shear flow" : "") +
                             ", grains counted in every slab they overlap",
                         {},
                         {}});
  }
  opt.hooks.push_back({o_.every, [this](const State& s) { sample(s); }});
  // The VTK files and the caller's outputs (frames) end with the run's last state, as the stats
  // do (--steps 250 with --every 100 wrote them for steps 0, 100 and 200 only): each remembers the
  // step it last took.
  std::vector<std::pair<std::function<void(const State&)>, std::shared_ptr<int64_t>>> ends;
  auto ending = [&](const PeriodicHook& h) {
    auto last = std::make_shared<int64_t>(-1);
    ends.emplace_back(h.fn, last);
    opt.hooks.push_back({h.every, [fn = h.fn, last](const State& s) {
                           *last = s.step;
                           fn(s);
                         }});
  };
  if (vtk_)
    ending({o_.vtk_every > 0 ? o_.vtk_every : o_.every, [this](const State& s) {
              if (!vtk_error_.empty()) return;
              try {
                vtk_->write(sim_.model(), s, module_grid_fields(sim_.model(), s));
              } catch (const IoError& e) {
                vtk_error_ = e.what();
              }
            }});
  if (profile_axis_ >= 0)
    opt.hooks.push_back({o_.every, [this](const State& s) {
                           if (!at_or_after(s.t, o_.average_from)) return;
                           VelocityProfile p =
                               velocity_profile(sim_.model(), s, profile_slabs_, profile_axis_, profile_component_);
                           if (profiles_[0].x.empty()) profiles_[0].x = std::move(p.y);
                           profiles_[0].add(p.vx, p.count);
                         }});
  for (const PeriodicHook& h : extra_) ending(h);
  // The modules' notes go into the summary's warnings too.
  opt.on_notice = [this, tell = opt.on_notice](const std::string& n) {
    warnings_.push_back(n);
    if (tell) tell(n);
  };
  kept_.reset();
  const RunReport rep = sim_.run(opt);
  // The end is sampled once, whatever --every. After a failure the end is the last good state
  // (the failed step's state is no sample), which the stats and the summary's last values then
  // show, as its checkpoint does.
  if (rep.end == RunEnd::kFailed) kept_ = sim_.last_good_state();
  sample(kept_state());
  if (rep.end != RunEnd::kFailed)
    for (const auto& [fn, last] : ends)
      if (*last != sim_.state().step) sim_.within([&, f = fn] { f(sim_.state()); });
  wall_s_ += rep.wall_s;
  steps_ += rep.steps_done;
  return rep;
}

int RunJob::write_outputs(SummaryInput& sum, int code) {
  auto failed_output = [&](const std::string& what) {
    add_output_error(what);
    if (code == 0) code = static_cast<int>(ExitCode::kIo);
  };
  try {
    if (stats_) stats_->flush();
  } catch (const IoError& e) {
    failed_output(e.what());
  }
  if (!vtk_error_.empty()) failed_output("VTK output stopped (the run went on): " + vtk_error_);
  if (code == 0 && !output_errors_.empty()) code = static_cast<int>(ExitCode::kIo);
  sum.exit_code = code;
  sum.warnings.insert(sum.warnings.end(), warnings_.begin(), warnings_.end());
  sum.warnings.insert(sum.warnings.end(), output_errors_.begin(), output_errors_.end());
  if (!o_.summary.empty()) {
    try {
      write_summary(o_.summary, sum, sim_, stats());
    } catch (const IoError& e) {
      std::cerr << "silt: " << e.what() << "\n";
      code = static_cast<int>(ExitCode::kIo);
    }
  }
  return code;
}

int RunJob::finish(const RunReport& rep, int interrupted) {
  const Model& m = sim_.model();
  int code = 0;
  if (rep.end == RunEnd::kFailed) code = static_cast<int>(ExitCode::kNumerical);
  if (rep.end == RunEnd::kInterrupted) code = interrupted;
  if (code == 0 && !output_errors_.empty()) code = static_cast<int>(ExitCode::kIo);
  // The checkpoints first: the summary records whether they could be written.
  if (rep.end == RunEnd::kFailed) {
    const std::string path = last_good_path_for(o_, inputs_);
    if (!kept_) kept_ = sim_.last_good_state();
    if (write_last_good(path, m, *kept_, *this)) last_good_ = path;
  }
  if (!o_.save.empty() && rep.end != RunEnd::kFailed) {
    try {
      write_checkpoint(o_.save, m, sim_.state());
    } catch (const IoError& e) {
      add_output_error(e.what());
      if (code == 0) code = static_cast<int>(ExitCode::kIo);
      // The final state is kept where it can be: under the checkpoint's name in the working
      // directory (its own directory removed during the run lost the run).
      const std::string there = free_checkpoint_path(std::filesystem::path(o_.save).filename().string(), o_, inputs_);
      if (!there.empty() && write_last_good(there, m, sim_.state(), *this))
        add_output_error("the final state was written to '" + there + "' instead");
    }
  }
  SummaryInput sum;
  sum.scene = o_.scene;
  sum.status = status(rep.end);
  sum.wall_s = wall_s_;
  sum.steps_run = steps_;
  sum.average_from = o_.average_from;
  sum.profiles = profiles_;
  if (preparation_) sum.preparation = &*preparation_;
  if (kept_) sum.kept = &*kept_;
  if (m.until_static.on && rep.end == RunEnd::kDone)
    sum.warnings.push_back("run.stop_when_static: no equilibrium within the run length");
  if (m.stop_when_steady && rep.end == RunEnd::kDone)
    sum.warnings.push_back("run.stop_when_steady: no steady state within the run length");
  // (every mean was null, without a word)
  if (!at_or_after(sim_.state().t, o_.average_from))
    sum.warnings.push_back("the averages start at t = " + format_number(o_.average_from) +
                           ", after the run's end (t = " + format_number(sim_.state().t) + "): no sample is averaged");
  return write_outputs(sum, code);
}

int RunJob::finish_preparation(const PreparationReport& prep, int interrupted) {
  const bool failed = prep.end == RunEnd::kFailed;
  if (failed && prep.last_good) {
    const std::string path = last_good_path_for(o_, inputs_);
    if (write_last_good(path, sim_.model(), *prep.last_good, *this)) last_good_ = path;
  }
  SummaryInput sum;
  sum.scene = o_.scene;
  sum.status = status(prep.end);
  sum.wall_s = prep.wall_s;
  sum.average_from = o_.average_from;
  sum.preparation = &prep;
  if (failed) {
    sum.failure = prep.failure_detail;
    sum.failure.failed = true;
  }
  sum.warnings.push_back("the preparation (prepare.compress) " + std::string(failed ? "failed" : "was interrupted") +
                         " after " + std::to_string(prep.steps) + " steps; the run did not start");
  return write_outputs(sum, failed ? static_cast<int>(ExitCode::kNumerical) : interrupted);
}

}  // namespace silt
