// `silt run`: the headless main job.
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cmath>
#include <iostream>
#include <sstream>

#include "shell/commands.hpp"
#include "shell/progress.hpp"
#include "shell/scene_loading.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/render.hpp"
#include "silt/simulation.hpp"

namespace silt::cli {
namespace {

std::atomic<bool> g_interrupt{false};
extern "C" void on_sigint(int) { g_interrupt.store(true); }

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(list);
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string stem_of(const std::string& path) {
  const auto dot = path.rfind('.');
  const auto slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path;
  return path.substr(0, dot);
}

// Procedure O before the run (Model::prepare): the prepared packing replaces the initial state.
// Returns an exit code, 0 when the run can go on; `warning` is set when the packing is not static.
int prepare(Simulation& sim, const RunArgs& a, std::string& warning) {
  const Model& model = sim.model();
  PreparationReport prep;
  g_interrupt = false;
  std::signal(SIGINT, on_sigint);
  if (!a.quiet) std::cerr << "silt: preparing: isotropic compression at P = " << model.box_control.pressure << "\n";
  sim.restore(prepare_packing(model, a.threads, &prep, &g_interrupt));
  std::signal(SIGINT, SIG_DFL);
  if (prep.end == RunEnd::kFailed) return report_error("numerical failure during the preparation: " + prep.failure, 3);
  if (prep.end == RunEnd::kInterrupted) return report_error("interrupted during the preparation", 130);
  if (!a.quiet)
    std::fprintf(stderr, "silt: prepared in %lld steps (%.1f s): phi = %.5f%s\n", static_cast<long long>(prep.steps),
                 prep.wall_s, measure(model, sim.state()).phi, prep.end == RunEnd::kStatic ? ", static" : "");
  if (prep.end != RunEnd::kStatic) warning = "prepare.max_steps: the compression did not reach equilibrium";
  return 0;
}

}  // namespace

int run_command(const RunArgs& a) {
  int code = 0;
  auto loaded = load_model(a.scene, a.sets, code);
  if (!loaded) return code;
  Model& m = *loaded;
  int64_t steps = m.run_steps;
  if (a.steps >= 0) steps = a.steps;
  if (a.time >= 0) {
    const double n = std::ceil(a.time / m.dt - 1e-9);
    if (!(n < 9e18)) return report_error("--time: too long, more than 9e18 time steps", 1);
    steps = static_cast<int64_t>(n);
  }
  if (steps <= 0 && a.steps != 0)
    return report_error("no run length: give --steps or --time, or [run] steps or time in the scene", 1);
  const std::vector<std::string> names = a.observe.empty() ? m.observe : split_names(a.observe);
  std::optional<Observer> observer;
  try {
    observer.emplace(m, names);
  } catch (const std::invalid_argument& e) {
    return report_error(std::string("--observe: ") + e.what(), 1);
  }
  const int64_t every = a.every > 0 ? a.every : m.sample_every;
  std::optional<StatsWriter> stats;
  try {
    stats.emplace(a.stats, names);
  } catch (const IoError& e) {
    return report_error(e.what(), 4);
  }
  const bool until_static = m.until_static.on;
  std::string prep_warning;
  std::vector<std::string> restore_warnings;  // parameters of the checkpoint's run that differ
  Simulation sim(std::move(m), a.threads);
  const Model& model = sim.model();
  if (!a.restore.empty()) {
    try {
      sim.restore(read_checkpoint(a.restore, model, &restore_warnings));
    } catch (const IoError& e) {
      return report_error(e.what(), 4);
    }
    for (const std::string& w : restore_warnings) std::cerr << "silt: warning: " << w << "\n";
  } else if (model.prepare.compress) {
    if (const int prep_code = prepare(sim, a, prep_warning); prep_code != 0) return prep_code;
  }

  std::unique_ptr<render::FrameWriter> frames;
  if (!a.frames.empty()) {
    try {
      frames = std::make_unique<render::FrameWriter>(a.frames);
    } catch (const IoError& e) {
      return report_error(e.what(), 4);
    }
  }
  std::unique_ptr<VtkWriter> vtk;
  if (!a.vtk.empty()) {
    try {
      vtk = std::make_unique<VtkWriter>(a.vtk);
    } catch (const IoError& e) {
      return report_error(e.what(), 4);
    }
  }
  const int64_t frame_every =
      a.frame_every > 0 ? a.frame_every : (model.render.every > 0 ? model.render.every : model.sample_every);

  SummaryInput sum;
  g_interrupt = false;
  std::signal(SIGINT, on_sigint);
  Progress progress(!a.quiet && ::isatty(2), sim.state().step, steps, model.n_grains);
  RunOptions opt;
  opt.steps = steps;
  opt.hooks.push_back({every, [&](const State& s) { stats->add(observer->sample(model, s), s.t); }});
  std::string vtk_error;
  if (vtk)
    opt.hooks.push_back({a.vtk_every > 0 ? a.vtk_every : model.sample_every, [&](const State& s) {
                           if (!vtk_error.empty()) return;
                           try {
                             vtk->write(model, s);
                           } catch (const IoError& e) {
                             vtk_error = e.what();
                           }
                         }});
  std::string frame_error;
  if (frames)
    opt.hooks.push_back({frame_every, [&](const State& s) {
                           if (!frame_error.empty()) return;
                           try {
                             frames->submit(render::build_render_scene(model, s, model.render));
                           } catch (const std::exception& e) {
                             frame_error = e.what();
                           }
                         }});
  if (model.shear.on) {
    // Slabs about one grain diameter thick, time-averaged from --average-from on.
    const int slabs = std::clamp(static_cast<int>(sim.state().box.len[1] / model.a_max), 4, 40);
    sum.profiles.push_back({"vx(y)", "y / L_y (slab centres); mean x velocity with the shear flow, grains counted in every slab they overlap", {}, {}});
    opt.hooks.push_back({every, [&, slabs](const State& s) {
                           if (s.t < a.average_from) return;
                           VelocityProfile p = velocity_profile(model, s, slabs);
                           if (sum.profiles[0].x.empty()) sum.profiles[0].x = std::move(p.y);
                           sum.profiles[0].samples.push_back(std::move(p.vx));
                         }});
  }
  opt.interrupt = &g_interrupt;
  opt.stop_when_static = until_static;
  opt.on_progress = [&progress](const State& s) { progress.update(s); };
  const RunReport rep = sim.run(opt);
  progress.update(sim.state());
  progress.finish();
  if (frames) {
    frames->finish();
    if (frame_error.empty()) frame_error = frames->error();
    if (!frame_error.empty()) sum.warnings.push_back("frames stopped: " + frame_error);
  }
  std::signal(SIGINT, SIG_DFL);

  sum.scene = a.scene;
  sum.wall_s = rep.wall_s;
  sum.steps_run = rep.steps_done;
  sum.average_from = a.average_from;
  switch (rep.end) {
    case RunEnd::kDone: sum.status = "ok"; break;
    case RunEnd::kStatic: sum.status = "static"; break;
    case RunEnd::kInterrupted: sum.status = "interrupted"; code = 130; break;
    case RunEnd::kFailed: sum.status = "failed"; code = 3; break;
  }
  if (until_static && rep.end == RunEnd::kDone)
    sum.warnings.push_back("run.stop_when_static: no equilibrium within the run length");
  if (!prep_warning.empty()) sum.warnings.push_back(prep_warning);
  sum.warnings.insert(sum.warnings.end(), restore_warnings.begin(), restore_warnings.end());
  sum.exit_code = code;
  try {
    stats->flush();
    if (rep.end == RunEnd::kFailed) {
      std::cerr << "silt: numerical failure at " << sim.state().failure.message << "\n";
      const std::string base = !a.summary.empty() ? a.summary : a.stats;
      if (!base.empty()) {
        const std::string ck = stem_of(base) + ".last_good.ckpt";
        const State good = sim.last_good_state();
        write_checkpoint(ck, model, good);
        std::cerr << "silt: last good state (step " << good.step << ") written to " << ck << "\n";
      }
    }
    if (!a.summary.empty()) write_summary(a.summary, sum, sim, *stats);
    if (!a.save.empty() && rep.end != RunEnd::kFailed) write_checkpoint(a.save, model, sim.state());
  } catch (const IoError& e) {
    return report_error(e.what(), 4);
  }
  if (!frame_error.empty()) {
    report_error("frames stopped (the run went on): " + frame_error, 4);
    if (code == 0) code = 4;
  }
  if (!vtk_error.empty()) {
    report_error("VTK output stopped (the run went on): " + vtk_error, 4);
    if (code == 0) code = 4;
  }
  const double rate = rep.wall_s > 0 ? model.n_grains * static_cast<double>(rep.steps_done) / rep.wall_s : 0;
  std::printf("%s: %lld steps (t = %.6g s) in %.3f s, %.4g grain-steps/s on %d thread(s); status %s\n",
              a.scene.c_str(), static_cast<long long>(rep.steps_done), sim.state().t, rep.wall_s, rate, sim.threads(),
              sum.status.c_str());
  return code;
}

}  // namespace silt::cli
