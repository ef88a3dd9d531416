// A shell session: the loaded scene, its simulation, runs in the foreground or the background,
// and the commands of the shell's language acting on them. Used by `silt shell` and `silt play`.
//
// Threads: commands arrive on one thread (the REPL's). A background run (`start`) owns the
// simulation between steps; any command that reads or changes it while it runs is handed to the
// run loop and executed at the next step boundary (`at_boundary`), so a command never sees half a
// step, and steering takes effect exactly between two steps. The run serves every request queued
// while it goes on, the last ones as it ends, so none is left behind for a later run.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "shell/command_parser.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/render.hpp"
#include "silt/run_job.hpp"
#include "silt/simulation.hpp"

namespace silt::shell {

class Session {
 public:
  Session(std::ostream& out, std::ostream& err, int threads);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Executes one line. Returns false on an error, whose message went to err prefixed by
  // `where` ("script:12: ") when given. Never throws.
  bool execute(const std::string& line, const std::string& where = "");
  // The exit code the last failed line asks for (INTERFACE.md): 3 after a numerical failure of a
  // run (also one inside a sourced script), else 2.
  int last_error_code() const { return last_error_code_; }
  // The failure of a background run that ended on it since the last call, "" when none.
  std::string take_background_failure();
  // An output (frames, VTK files) that a background run could no longer write and no command has
  // reported yet, "" when none: `silt play` exits 4 on it, as `silt run` does.
  std::string take_output_error();
  // Both, as the lines a script's player reports ("the background run failed: ...", "the run's
  // output: ...") and the exit code they ask for: 3 for a failure, 4 for a lost output (the higher
  // when both), 0 when neither.
  struct Unreported {
    std::vector<std::string> lines;
    int code = 0;
  };
  Unreported take_unreported();
  // The script `silt play` reads: relative input files (load, source, restore) not found in the
  // current directory are looked for in its directory, and no command writes over it.
  void set_script(const std::string& path);
  // `source`d lines echoed as `silt play` echoes its own (SCRIPT:LINE> command).
  void set_echo_sources(bool on) { echo_sources_ = on; }
  // Sourced scripts go on after an error (`silt play --keep-going`).
  void set_keep_going(bool on) { keep_going_ = on; }
  bool quit_requested() const { return quit_; }
  bool running() const { return background_.joinable() && !bg_done_; }
  bool loaded() const { return sim_ != nullptr; }
  // Ctrl-C: pause the run in progress (foreground or background) at the next step boundary, and
  // abandon the script being sourced. Safe in a signal handler.
  void interrupt();
  // Lines produced by a background run (watch, end of run), for the REPL to print.
  std::vector<std::string> take_messages();
  std::string prompt() const;
  // A progress line on err during foreground runs (the REPL turns it on for terminals).
  void set_progress(bool on) { progress_ = on; }
  // Completion candidates for the word being typed, by what the command expects; nullopt where
  // the word is a file name (load, source, save, restore, render, frames), for the line editor.
  std::optional<std::vector<std::string>> complete(const std::string& line_before_word, const std::string& word) const;

 private:
  using Handler = void (Session::*)(const Command&);
  void dispatch(const Command& c);
  // Commands.
  void cmd_load(const Command& c);
  void cmd_reload(const Command& c);
  void cmd_check(const Command& c);
  void cmd_run(const Command& c);
  void cmd_start(const Command& c);
  void cmd_stop(const Command& c);
  void cmd_wait(const Command& c);
  void cmd_set(const Command& c);
  void cmd_get(const Command& c);
  void cmd_params(const Command& c);
  void cmd_print(const Command& c);
  void cmd_watch(const Command& c);
  void cmd_stats(const Command& c);
  void cmd_profile(const Command& c);
  void cmd_render(const Command& c);
  void cmd_frames(const Command& c);
  void cmd_vtk(const Command& c);
  void cmd_save(const Command& c);
  void cmd_hash(const Command& c);
  void cmd_freeze(const Command& c);
  void cmd_fields(const Command& c);
  void cmd_field(const Command& c);
  void cmd_restore(const Command& c);
  void cmd_reset(const Command& c);
  void cmd_source(const Command& c);
  void cmd_help(const Command& c);
  void cmd_quit(const Command& c);

  // `set`'s parts (session_set.cpp): the change read, steered, or compiled, and the notes after it.
  struct SetChange;
  SetChange read_set(const Command& c);
  bool steer_set(const SetChange& ch);
  void recompile_set(const SetChange& ch);
  Model compile_set(const SetChange& ch) const;
  // (`kept`: the state kept through the change, or null)
  void set_notes(const SetChange& ch, const State* kept);

  // Helpers.
  Simulation& sim();  // throws when no scene is loaded
  void require_stopped(const std::string& what) const;
  // A simulation of `m` from `keep` (else the scene's own state) in place of the current one. A
  // kept state that cannot be solved under m (a paste's velocities solved again) installs nothing,
  // and the failure's message is returned ("" when installed).
  std::string install(Model m, const std::optional<State>& keep);
  // The packing the model's compression prepares, from a fresh state or going on from `from` (a
  // compression's state before its end); a failure throws, the shell's state as it was.
  State compressed(const Model& m, const State* from);
  // The watched observables under the model installed (off, saying why, when it has them not).
  void rewatch();
  // The scene file as loaded (or reloaded) with the changes typed since: the file is not read
  // again (a file edited since is read by `reload`), or `base` with them.
  SceneDesc scene_with(const std::vector<Override>& changes, const SceneDesc* base = nullptr) const;
  // An input file: as given, else relative to the script's directory; throws when unreadable.
  std::string input_path(const std::string& file) const;
  void run_for(const RunLength& len, bool background);
  RunOptions run_options(const RunLength& len, bool background);
  void at_boundary(const std::function<void()>& fn);
  void serve_requests(bool last);
  void say(const std::string& line, bool from_background);
  static StatsWriter reseries(const StatsWriter& old, const std::string& path);

  std::ostream& out_;
  std::ostream& err_;
  int threads_;
  bool quit_ = false;
  bool progress_ = false;
  int source_depth_ = 0;
  int last_error_code_ = 0;
  // The scripts being read (play's, sourced ones), the innermost last: relative input files are
  // also looked for beside it.
  std::vector<std::string> scripts_;
  // IoError when `path` is the scene file, a checkpoint its grains were read from or a script
  // being read (a `stats` onto the script played replaced its next lines with CSV rows).
  void check_not_inputs(const std::string& path, const std::string& what) const;
  // The checkpoints restored in this session: IoError when `path`, a stats file or an image, is
  // one of them (a `save` may replace one: a state saved back).
  std::vector<std::string> restored_;
  void check_not_restored(const std::string& path, const std::string& what) const;

  std::string scene_file_;
  SceneDesc scene_read_;  // the file as `load` or `reload` read it, no value set
  std::vector<Override> overrides_;
  std::unique_ptr<Simulation> sim_;
  std::optional<StatsWriter> stats_;  // samples of the scene's observables since load (or reset)
  bool echo_sources_ = false;
  bool keep_going_ = false;
  std::string stats_file_;  // where they are written ("" nowhere)
  // IoError when `path` is the scene file or the stats file being written (a `save` there replaced
  // the stats with a checkpoint, and later rows went to a deleted file).
  void check_not_open_file(const std::string& path, const std::string& what) const;
  // IoError when `path` is a name the frames or the VTK files being written take in their
  // directory (a stats file named frame_000001.png there was overwritten, or removed).
  void check_not_series_file(const std::string& path, const std::string& what) const;
  // IoError when the stats file being written has a name the series `owns` would take in `dir`.
  void check_not_series_dir(const std::string& dir, bool (*owns)(const std::string&, const std::string&),
                            const std::string& what) const;
  int64_t stats_every_ = 0;  // sampling interval (0: the scene's output.every)

  struct Watch {
    std::vector<std::string> names;
    int64_t every = 0;
    std::optional<Observer> observer;
    int64_t last_step = -1;  // of the last line (-1: none yet)
  };
  Watch watch_;
  std::unique_ptr<render::FrameWriter> frames_;
  std::string frames_dir_;  // where frames_ writes
  int64_t frames_every_ = 0;
  int64_t frames_last_step_ = -1;  // of the last frame submitted (-1: none yet)
  // A state other than the one the frames, the VTK files and the watch followed (another scene, a
  // reset, a restore), at `step`: they take it at their steps again from there (the first frame
  // of a scene loaded after a run that ended at a frame's step was skipped).
  void rewind_series(int64_t step);
  std::unique_ptr<VtkWriter> vtk_;
  std::string vtk_dir_;  // where vtk_ writes
  int64_t vtk_every_ = 0;
  int64_t vtk_last_step_ = -1;  // of the last files written (-1: none yet)
  std::string vtk_error_;       // the VTK output stopped on it
  // The outputs' errors not yet reported (guarded by mutex_), and which of them were noted.
  std::string output_error_;
  bool frames_error_noted_ = false, vtk_error_noted_ = false, stats_error_noted_ = false;
  // Notes the frames' and VTK's errors not noted yet into output_error_ (any thread); returns them.
  std::string note_output_errors();
  // Throws IoError with the errors noted and not reported (a command's error: exit 4 in play).
  void report_output_errors();
  std::unique_ptr<render::Rasterizer> raster_;

  // Background run and step-boundary requests.
  std::thread background_;
  std::atomic<bool> bg_done_{true};
  std::atomic<bool> interrupt_{false};
  std::atomic<bool> script_interrupted_{false};  // Ctrl-C: stop sourcing
  std::atomic<double> shown_t_{0};               // t for the prompt, published at step boundaries
  bool background_started_ = false;              // a `start` not yet followed by `stop`
  int64_t background_end_step_ = 0;              // where the last background run ended
  bool background_interrupted_ = false;          // and whether Ctrl-C ended it
  bool background_waited_ = false;               // the last `start` was followed by `wait`, not `stop`
  // How a `run until` ended the run: its condition met, or made impossible by t and step.
  enum class UntilEnd : uint8_t { kNone, kMet, kNeverHolds };
  std::atomic<UntilEnd> until_end_{UntilEnd::kNone};
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> requests_;
  std::atomic<bool> has_requests_{false};
  std::deque<std::string> messages_;
  std::string background_failure_;
};

// The keys of the schema before a scene is loaded (no tables yet).
inline const SceneDesc kNoScene{};

// Why `path` cannot be read as an input file ("'x' is a directory, not a file"), or "" when it can.
std::string input_file_problem(const std::string& path);

}  // namespace silt::shell
