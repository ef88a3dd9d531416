// `silt run`: the headless main job.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "shell/commands.hpp"
#include "shell/progress.hpp"
#include "shell/scene_loading.hpp"
#include "shell/stop_signals.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/render.hpp"
#include "silt/run_job.hpp"
#include "silt/simulation.hpp"
#include "silt/text.hpp"

namespace silt::cli {
namespace {

std::atomic<bool> g_interrupt{false};

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(list);
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

// Procedure O before the run (Model::prepare): the prepared packing replaces the initial state.
// Returns an exit code, 0 when the run can go on; a failure or an interruption is written up by
// the job (summary, last good state). `warning` is set when the packing is not static.
// `from`: a compression's state before its end (restored), which the compression goes on with.
int prepare(Simulation& sim, const RunArgs& a, RunJob& job, std::string& warning, const State* from) {
  const Model& model = sim.model();
  PreparationReport prep;
  g_interrupt = false;
  State packed;
  {
    StopSignals stop(&g_interrupt);
    if (!a.quiet) {
      std::cerr << "silt: preparing: isotropic compression at P = " << preparation_pressure(model);
      if (from) std::cerr << ", going on from step " << from->step << " of " << a.restore;
      std::cerr << "\n";
    }
    packed = prepare_packing(model, a.threads, &prep, &g_interrupt, from);
  }
  if (prep.end == RunEnd::kFailed || prep.end == RunEnd::kInterrupted) {
    if (prep.end == RunEnd::kFailed)
      std::cerr << "silt: numerical failure during the preparation: " << prep.failure << "\n";
    else std::cerr << "silt: interrupted during the preparation\n";
    const int code = job.finish_preparation(prep, StopSignals::exit_code());
    if (!job.last_good_path().empty())
      std::cerr << "silt: the compression's last good state written to " << job.last_good_path() << "\n";
    return code;
  }
  sim.restore(std::move(packed));
  job.prepared(prep);
  if (!a.quiet)
    std::fprintf(stderr, "silt: prepared in %lld steps (%.1f s): phi = %.5f%s\n", static_cast<long long>(prep.steps),
                 prep.wall_s, measure(model, sim.state(), measure_part::kGrains).phi,
                 prep.end == RunEnd::kStatic ? ", static" : "");
  if (prep.end != RunEnd::kStatic && !prep.reached_phi) {
    // Said now as well as in the summary: what follows starts from a packing still moving.
    // (the compression's phi: the state's is after prepare.dilation)
    warning = "prepare.max_steps: the compression did not reach equilibrium in " + std::to_string(prep.steps) +
              " steps (phi = " + format_number(prep.phi, 5) + "); the run starts from a packing still in motion";
    std::cerr << "silt: warning: " << warning << "\n";
  }
  return 0;
}

// Two outputs written to one file would leave only the last, or an output directory would remove a
// file the run reads: why, or "" when every file is its own (a device such as /dev/stdout may take
// several outputs).
std::string shared_output(const RunArgs& a) {
  const std::vector<std::pair<std::string, std::string>> files = {
      {"--stats", a.stats}, {"--summary", a.summary}, {"--save", a.save}};
  const std::string each = ": each would overwrite the other";
  if (std::string clash = clashing_outputs(files, a.vtk); !clash.empty()) return clash + each;
  // (a stats file named as a frame in the frames' directory was overwritten by that frame)
  for (const auto& [option, path] : files)
    if (!path.empty() && render::FrameWriter::owns(path, a.frames))
      return option + " " + path + " is a frame's name in --frames " + a.frames + each;
  // The files read too: --frames removes an earlier run's frames, and a checkpoint restored from
  // DIR/frame_000000.png was removed (VTK's numbered files likewise).
  for (const auto& [option, path] :
       {std::pair<std::string, std::string>{"the scene", a.scene}, {"--restore", a.restore}}) {
    if (path.empty()) continue;
    if (render::FrameWriter::owns(path, a.frames))
      return option + " " + path + " is a frame's name in --frames " + a.frames + ", which removes it";
    if (VtkWriter::owns(path, a.vtk))
      return option + " " + path + " is a VTK file's name in --vtk " + a.vtk + ", which removes it";
  }
  return "";
}

}  // namespace

int run_command(const RunArgs& a) {
  if (const std::string shared = shared_output(a); !shared.empty()) return report_error(shared, 1);
  int code = 0;
  // --steps and --time replace the scene's [run] length before it is compiled, so that a run.time
  // too long for the scene's step does not refuse a run of N steps. With --time the run's length
  // is opt.time, not the model's (the key only takes the scene's out of the way).
  const bool cli_length = a.steps >= 0 || a.time >= 0;
  const std::optional<Override> length =
      cli_length ? std::optional(Override{"run.steps", std::to_string(std::max<int64_t>(a.steps, 0))}) : std::nullopt;
  auto loaded = load_model(a.scene, a.sets, code, length);
  if (!loaded) return code;
  Model& m = *loaded;
  RunOptions opt;
  const bool scene_length = !cli_length;
  if (a.steps >= 0) {
    opt.steps = a.steps;
    opt.time = -1;
  }
  if (a.time >= 0) {
    if (steps_in(a.time, m.dt) < 0) return report_error("--time: " + too_many_steps(m.dt), 1);
    opt.time = a.time;
  }
  if (scene_length && !m.gives_run_length())
    return report_error("no run length: give --steps or --time, or [run] steps or time in the scene", 1);
  RunJobOptions jo;
  jo.scene = a.scene;
  jo.restored = a.restore;
  jo.observe = a.observe.empty() ? std::vector<std::string>{} : split_names(a.observe);
  jo.every = a.every;
  jo.stats = a.stats;
  jo.summary = a.summary;
  jo.save = a.save;
  jo.vtk = a.vtk;
  jo.vtk_every = a.vtk_every;
  jo.average_from = a.average_from;
  // A failed run keeps its last good state (INTERFACE.md) even without an output file to put it
  // beside: then in the current directory, named after the scene.
  jo.last_good_fallback = std::filesystem::path(a.scene).stem().string() + ".last_good.ckpt";
  // The observables are checked before anything is prepared or written.
  try {
    Observer check(m, jo.observe.empty() ? m.observe : jo.observe);
  } catch (const std::invalid_argument& e) {
    return report_error(std::string("--observe: ") + e.what(), 1);
  }
  std::vector<std::string> restore_warnings;  // parameters of the checkpoint's run that differ
  Simulation sim(std::move(m), a.threads);
  const Model& model = sim.model();
  if (!a.restore.empty()) {
    try {
      std::vector<uint8_t> frozen;  // grains the checkpoint's run froze (`freeze`), frozen here too
      State st = read_checkpoint(a.restore, model, &restore_warnings, &frozen);
      if (in_compression(st) && std::find(frozen.begin(), frozen.end(), 1) != frozen.end())
        return report_error("--restore " + a.restore + ": a compression's state with grains frozen by freeze", 1);
      if (const int64_t n = sim.freeze_grains(frozen); n > 0)
        std::cerr << "silt: " << n << " grain(s) frozen in the checkpoint (by `freeze`) are frozen in this run too\n";
      sim.restore(std::move(st));
    } catch (const IoError& e) {
      return report_error(e.what(), 4);
    } catch (const std::invalid_argument& e) {
      return report_error("--restore " + a.restore + ": " + e.what(), 1);
    }
    for (const std::string& w : restore_warnings) std::cerr << "silt: warning: " << w << "\n";
    // (it did so without a word, where a stats file or a summary named so is refused)
    if (overwrites(a.save, a.restore))
      std::cerr << "silt: note: --save " << a.save << " replaces the checkpoint restored (a run continued in place)\n";
  }
  // A compression's last good state (a failed preparation's) is compressed on, not run as it is:
  // the scene's run started shearing a half-compressed packing from its step 21,599.
  const bool resume = !a.restore.empty() && in_compression(sim.state());
  if (resume && !model.prepare.compress)
    return report_error("--restore " + a.restore + ": a compression's state before its end (step " +
                            std::to_string(sim.state().step) +
                            "), and this scene prepares none: give prepare.compress = true to go on compressing it",
                        1);
  // The scene's own length runs to its end from the state it starts from (a restored one
  // continues to the scene's end, as the shell's `restore X`, `run` does; it ran the whole length
  // again). An adaptive step runs the scene's time, not a step count made from the first step.
  if (scene_length) {
    const RunOptions left = sim.scene_run_left();
    if (left.time < 0 && left.steps <= 0 && !a.restore.empty() && !resume)
      return report_error("the checkpoint is at the scene's end (t = " + format_number(sim.state().t) +
                              model.unit("s") + ", step " + std::to_string(sim.state().step) +
                              "): give --steps or --time to go on",
                          1);
    opt.steps = left.steps;
    opt.time = left.time;
  }
  // Every output is opened or checked before the first step (of the preparation too), the frame
  // directory before the stats file, which opening truncates: a refused run keeps it.
  // (The frame writer itself, which removes an earlier run's frames, once the preparation is done.)
  std::optional<RunJob> job;
  try {
    if (!a.frames.empty()) make_output_directory(a.frames, "frame");
    job.emplace(sim, jo);
  } catch (const IoError& e) {
    return report_error(e.what(), 4);
  }
  if (job->vtk_removed() > 0)
    std::cerr << "silt: " << job->vtk_removed() << " VTK file(s) of an earlier run removed from " << a.vtk << "\n";
  std::string prep_warning;
  if ((a.restore.empty() || resume) && model.prepare.compress) {
    // (a copy: the preparation's end replaces the simulation's state)
    const std::optional<State> from = resume ? std::optional<State>(sim.state()) : std::nullopt;
    if (const int prep_code = prepare(sim, a, *job, prep_warning, from ? &*from : nullptr); prep_code != 0)
      return prep_code;
    if (resume && scene_length) {  // the scene's whole run, from the packing at t = 0
      const RunOptions left = sim.scene_run_left();
      opt.steps = left.steps;
      opt.time = left.time;
    }
  }
  std::unique_ptr<render::FrameWriter> frames;
  if (!a.frames.empty()) {
    try {
      frames = std::make_unique<render::FrameWriter>(a.frames);
    } catch (const IoError& e) {
      return report_error(e.what(), 4);
    }
  }
  // (--every stands for output.every here too: `--every 10` drew one frame where `--set
  // output.every=10` drew eleven)
  const int64_t frame_every = a.frame_every > 0        ? a.frame_every
                              : model.render.every > 0 ? model.render.every
                              : a.every > 0            ? a.every
                                                       : model.sample_every;
  std::string frame_error;
  // What a frame could not draw, each said once (a frame too narrow for its colour bar dropped it
  // without a word; the shell's `render` says it).
  std::vector<std::string> frame_warnings;
  if (frames)
    job->add_hook({frame_every, [&](const State& s) {
                     if (!frame_error.empty()) return;
                     try {
                       render::RenderScene rs = render::build_render_scene(model, s, model.render);
                       for (const std::string& w : rs.warnings)
                         if (frame_warnings.size() < 5 &&
                             std::find(frame_warnings.begin(), frame_warnings.end(), w) == frame_warnings.end())
                           frame_warnings.push_back(w);
                       frames->submit(std::move(rs));
                     } catch (const std::exception& e) {
                       frame_error = e.what();
                     }
                   }});
  if (!prep_warning.empty()) job->add_warning(prep_warning);
  for (const std::string& w : restore_warnings) job->add_warning(w);
  if (std::string w = sim.long_run_note(opt); !w.empty()) {
    w += ": give fewer with --steps or --time, or a longer step";
    std::cerr << "silt: warning: " << w << "\n";
    job->add_warning(w);
  }

  g_interrupt = false;
  StopSignals stop(&g_interrupt);
  const int64_t n_cells = model.n_cells();
  Progress progress(!a.quiet && ::isatty(2), sim.state().step, sim.steps_for(opt), model.n_grains, n_cells);
  opt.interrupt = &g_interrupt;
  opt.stop_when_static = model.until_static.on;
  opt.stop_when_steady = model.stop_when_steady;
  opt.on_progress = [&progress](const State& s) { progress.update(s); };
  opt.on_notice = [&progress](const std::string& n) {
    progress.finish();  // the warning on a line of its own
    std::cerr << "silt: warning: " << n << "\n";
  };
  const RunReport rep = job->run(opt);
  progress.update(sim.state());
  progress.finish();
  for (const std::string& w : frame_warnings) {
    std::cerr << "silt: warning: frames: " << w << "\n";
    job->add_warning("frames: " + w);
  }
  if (frames) {
    frames->finish();
    if (frame_error.empty()) frame_error = frames->error();
    if (!frame_error.empty()) job->add_output_error("frames stopped (the run went on): " + frame_error);
    if (frames->removed() > 0)
      std::cerr << "silt: " << frames->removed() << " frame(s) of an earlier run removed from " << a.frames << "\n";
  }
  if (rep.end == RunEnd::kFailed) std::cerr << "silt: numerical failure at " << sim.state().failure.message << "\n";
  if (rep.end == RunEnd::kInterrupted && StopSignals::caught() != SIGINT && StopSignals::caught() != 0)
    std::cerr << "silt: " << StopSignals::describe() << ": stopped at step " << sim.state().step
              << ", outputs written\n";
  code = job->finish(rep, StopSignals::exit_code());
  if (!job->last_good_path().empty())
    std::cerr << "silt: last good state (step " << sim.state().failure.step - 1 << ") written to "
              << job->last_good_path() << "\n";
  // Throughput: grain-steps, and cell-steps of a grid (a fluid's).
  const auto cells = static_cast<double>(n_cells);
  const double per_s = rep.wall_s > 0 ? static_cast<double>(rep.steps_done) / rep.wall_s : 0;
  std::string rate;
  char buf[64];
  if (model.n_grains > 0 || cells == 0) {
    std::snprintf(buf, sizeof buf, "%.4g grain-steps/s", static_cast<double>(model.n_grains) * per_s);
    rate = buf;
  }
  if (cells > 0) {
    std::snprintf(buf, sizeof buf, "%s%.4g cell-steps/s", rate.empty() ? "" : ", ", cells * per_s);
    rate += buf;
  }
  std::printf("%s: %lld steps (t = %.6g%s) in %.3f s, %s on %d thread(s); status %s\n", a.scene.c_str(),
              static_cast<long long>(rep.steps_done), job->kept_state().t, model.unit("s").c_str(), rep.wall_s,
              rate.c_str(), sim.threads(), RunJob::status(rep.end));
  return code;
}

}  // namespace silt::cli
