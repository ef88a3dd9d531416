// A run with its outputs: the observables sampled into the stats series, VTK files, a velocity
// profile, and at the end the summary, the last good state after a failure and the final
// checkpoint. `silt run` and the shell's runs are jobs; so will be the runs of a parameter sweep.
// Pictures are not the engine's: a caller adds a hook for its frames.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/simulation.hpp"

namespace silt {

struct RunJobOptions {
  std::string scene;  // as the summary names it
  // The checkpoint the state was restored from ("" none): like the scene (and the checkpoints its
  // grains were read from) no output overwrites it, but the final checkpoint may (a run continued
  // in place).
  std::string restored;
  std::vector<std::string> observe;  // the stats' observables (default: the scene's)
  int64_t every = 0;                 // samples every N steps (0: the scene's output.every)
  std::string stats;                 // stats CSV ("" none)
  std::string summary;               // summary JSON ("" none)
  std::string save;                  // checkpoint of the final state ("" none)
  std::string vtk;                   // VTK directory ("" none)
  int64_t vtk_every = 0;             // (0: output.every)
  double average_from = 0;           // means and errors over samples with t >= this [s]
  // Where a failed run's last good state goes when there is no summary, stats or checkpoint file
  // to put it beside ("" none: the shell keeps it in memory).
  std::string last_good_fallback;
  // Samples go into this series instead of a new one (the shell's, kept since the scene was
  // loaded); `observe` and `stats` are then its own.
  StatsWriter* series = nullptr;
};

class RunJob {
 public:
  // Checks the observables (std::invalid_argument), checks that no output would overwrite a file
  // the run reads or another output and that the stats, the summary and the checkpoint can be
  // written, then opens the VTK and stats outputs (IoError), before any step.
  RunJob(Simulation& sim, RunJobOptions options);
  ~RunJob();
  RunJob(const RunJob&) = delete;
  RunJob& operator=(const RunJob&) = delete;

  // Something else to do every N steps (frames).
  void add_hook(PeriodicHook hook) { extra_.push_back(std::move(hook)); }
  void add_warning(std::string w) { warnings_.push_back(std::move(w)); }
  // A failure of an output that the run went on without: reported on stderr now, in the
  // summary's warnings and by exit code 4 at the end.
  void add_output_error(std::string e);

  // The run, with the job's hooks added to opt's; the modules' notes (RunOptions::on_notice) also
  // go into the summary's warnings.
  RunReport run(RunOptions opt);
  // After the run: the stats flushed, the last good state written after a failure (beside the
  // summary, else the stats), the final checkpoint, then the summary. Returns the process's exit
  // code (0; 3 numerical failure; 4 an output failed; `interrupted` (130 for SIGINT, 143 for
  // SIGTERM) when stopped), the one the summary records; a file that cannot be written is
  // reported on stderr and makes it 4 (the summary too, when it is the summary).
  int finish(const RunReport& rep, int interrupted = 130);
  // A preparation (procedure O) that failed or was interrupted, so that the run never started:
  // after a failure its last good state is written (a checkpoint of the same grains, for
  // --restore); the summary says what happened. Returns 3 after a failure, `interrupted` after an
  // interruption, or 4 when an output could not be written.
  int finish_preparation(const PreparationReport& prep, int interrupted = 130);
  // A preparation that ended well, before the run: reported in the summary apart from the run.
  void prepared(const PreparationReport& prep) { preparation_ = prep; }

  const StatsWriter& stats() const { return o_.series ? *o_.series : *stats_; }
  // An earlier run's VTK files removed from the directory (0 without VTK output).
  int64_t vtk_removed() const;
  const Observer& observer() const { return *observer_; }
  // What the summary calls the end of the run: ok, static, interrupted, failed.
  static const char* status(RunEnd end);
  // Where finish() wrote the last good state, "" when it did not.
  const std::string& last_good_path() const { return last_good_; }
  // The state the run ends with as the user keeps it: after a failure the last good one (the
  // failed step's state is no result), else the simulation's.
  const State& kept_state() const { return kept_ ? *kept_ : sim_.state(); }

 private:
  Simulation& sim_;
  RunJobOptions o_;
  std::optional<Observer> observer_;
  std::optional<StatsWriter> stats_;
  std::unique_ptr<VtkWriter> vtk_;
  std::string vtk_error_;
  std::vector<ProfileSeries> profiles_;
  int profile_axis_ = -1, profile_component_ = 0, profile_slabs_ = 0;
  std::vector<PeriodicHook> extra_;
  std::vector<std::string> warnings_, output_errors_;
  std::string last_good_;
  std::vector<std::pair<std::string, std::string>> inputs_;  // the files the run read, and what each is
  std::optional<State> kept_;                                // after a failure: the last good state
  std::optional<PreparationReport> preparation_;
  void sample(const State& s);
  int write_outputs(SummaryInput& sum, int code);
  double wall_s_ = 0;
  int64_t steps_ = 0;
};

}  // namespace silt
