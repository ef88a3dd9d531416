// Session: loading, running (foreground and background), and the step-boundary machinery.
// The commands that only read or change things are in session_commands.cpp.
#include "shell/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <sstream>

#include "shell/progress.hpp"
#include "shell/table.hpp"
#include "silt/errors.hpp"
#include "silt/input_files.hpp"
#include "silt/module.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt::shell {
namespace {

// A foreground run that stopped on a numerical failure: an error of the command (exit code 3 in
// `silt play`), after the report and the return to the last good state.
class RunFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The fewest steps `until` takes at a fixed step dt from time t and step `step`, when its clauses
// are all joined by `and` and one of them asks t or step to reach a value: the run cannot stop
// before it. 0 when nothing bounds it so (`or`, other observables).
double until_steps_at_least(const Condition& c, double t, int64_t step, double dt) {
  for (bool joined : c.joined_by_and)
    if (!joined) return 0;
  double least = 0;
  for (const Clause& k : c.clauses) {
    if (k.op != ">=" && k.op != ">" && k.op != "==") continue;
    if (k.observable == "t") least = std::max(least, (k.value - t) / dt);
    if (k.observable == "step") least = std::max(least, k.value - static_cast<double>(step));
  }
  return least;
}

// Whether `until` can never hold however long the run: t and step only grow, so a term (clauses
// joined by `and`) that asks one of them to be below where it is, or above a value and below a
// smaller one, never holds ("step >= 10 and step < 5" ran without end). Only terms of t and step
// clauses that certainly fail count; any other term may hold.
bool until_never_holds(const Condition& c, double t, int64_t step) {
  for (size_t k = 0, e = 0; k < c.clauses.size(); k = e) {
    e = c.term_end(k);  // one term: clauses k .. e - 1
    bool never = false;
    for (const char* name : {"t", "step"}) {
      double lo = name[0] == 't' ? t : static_cast<double>(step), hi = HUGE_VAL;
      bool lo_strict = false, hi_strict = false;
      for (size_t j = k; j < e; ++j) {
        const Clause& cl = c.clauses[j];
        if (cl.observable != name) continue;
        // t within kTimeSlack of a value is at it (compare): "t <= 0.0003" holds at t =
        // 3.0000000000000003e-4 and "t < 0.0003" does not.
        const double slack = name[0] == 't' ? time_slack(cl.value) : 0;
        const double below = cl.op == ">" ? cl.value + slack : cl.value - slack;
        const double above = cl.op == "<" ? cl.value - slack : cl.value + slack;
        if ((cl.op == ">=" || cl.op == ">" || cl.op == "==") && below >= lo) {
          lo_strict = cl.op == ">" || (below == lo && lo_strict);
          lo = below;
        }
        if ((cl.op == "<" || cl.op == "<=" || cl.op == "==") && above <= hi) {
          hi_strict = cl.op == "<" || (above == hi && hi_strict);
          hi = above;
        }
      }
      // A step count is whole: its bounds are the whole steps within them ("step == 57.5" ran without
      // end, and so would "step > 56 and step < 57").
      if (name[0] == 's') {
        lo = lo_strict ? std::floor(lo) + 1 : std::ceil(lo);
        hi = hi_strict ? std::ceil(hi) - 1 : std::floor(hi);
        lo_strict = hi_strict = false;
      }
      never = never || lo > hi || (lo == hi && (lo_strict || hi_strict));
    }
    if (!never) return false;
  }
  return true;
}

}  // namespace

std::string input_file_problem(const std::string& path) {
  try {
    check_input_file(path, "file", std::numeric_limits<std::uintmax_t>::max());  // each reader has its bound
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

Session::Session(std::ostream& out, std::ostream& err, int threads) : out_(out), err_(err), threads_(threads) {}

Session::~Session() {
  if (background_.joinable()) {
    interrupt_ = true;
    background_.join();
  }
}

Simulation& Session::sim() {
  if (!sim_) throw std::runtime_error("no scene loaded (load FILE)");
  return *sim_;
}

void Session::require_stopped(const std::string& what) const {
  if (background_.joinable() && !bg_done_) throw std::runtime_error(what + " while a run goes on: stop it first");
}

void Session::interrupt() {
  interrupt_ = true;
  script_interrupted_ = true;
}

std::string Session::take_background_failure() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(background_failure_, std::string());
}

std::string Session::take_output_error() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(output_error_, std::string());
}

Session::Unreported Session::take_unreported() {
  Unreported u;
  if (const std::string failure = take_background_failure(); !failure.empty()) {
    u.lines.push_back("the background run failed: " + failure);
    u.code = static_cast<int>(ExitCode::kNumerical);
  }
  if (const std::string lost = take_output_error(); !lost.empty()) {
    u.lines.push_back("the run's output: " + lost);
    u.code = std::max(u.code, static_cast<int>(ExitCode::kIo));
  }
  return u;
}

std::string Session::note_output_errors() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string fresh;
  auto add = [&](const std::string& what) {
    output_error_ += (output_error_.empty() ? "" : "; ") + what;
    fresh += (fresh.empty() ? "" : "; ") + what;
  };
  if (frames_ && !frames_error_noted_)
    if (const std::string e = frames_->error(); !e.empty()) {
      add("frames stopped (the run went on): " + e);
      frames_error_noted_ = true;
    }
  // (rows a stats file could no longer take were lost without a word: play exited 0)
  if (stats_ && !stats_error_noted_ && !stats_->error().empty()) {
    add("stats file " + stats_file_ +
        " no longer written (the run went on; the samples are in memory): " + stats_->error());
    stats_error_noted_ = true;
  }
  if (!vtk_error_.empty() && !vtk_error_noted_) {
    add("vtk stopped (the run went on): " + vtk_error_);
    vtk_error_noted_ = true;
  }
  return fresh;
}

void Session::report_output_errors() {
  note_output_errors();
  if (std::string e = take_output_error(); !e.empty()) throw IoError(e);
}

std::string Session::input_path(const std::string& file) const {
  std::error_code ec;
  const std::filesystem::path p(file);
  // Beside the innermost script being read.
  const std::string script_dir =
      scripts_.empty() ? std::string() : std::filesystem::path(scripts_.back()).parent_path().string();
  if (!std::filesystem::exists(p, ec) && p.is_relative() && !script_dir.empty()) {
    const std::string beside = (std::filesystem::path(script_dir) / p).string();
    if (std::filesystem::exists(beside, ec)) return beside;
  }
  if (const std::string problem = input_file_problem(file); !problem.empty()) throw IoError(problem);
  return file;
}

SceneDesc Session::scene_with(const std::vector<Override>& changes, const SceneDesc* base) const {
  SceneDesc d = base ? *base : scene_read_;
  for (const Override& o : changes) apply_change(d, o, "set " + o.key);
  return d;
}

std::vector<std::string> Session::take_messages() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out(messages_.begin(), messages_.end());
  messages_.clear();
  return out;
}

void Session::say(const std::string& line, bool from_background) {
  if (from_background) {
    std::lock_guard<std::mutex> lock(mutex_);
    messages_.push_back(line);
  } else {
    out_ << line << "\n" << std::flush;
  }
}

std::string Session::prompt() const {
  if (!sim_) return "silt> ";
  char buf[96];
  std::snprintf(buf, sizeof buf, "silt[t=%.4g%s]> ", shown_t_.load(), running() ? " running" : "");
  return buf;
}

bool Session::execute(const std::string& line, const std::string& where) {
  // Reap a background run that ended by itself.
  if (background_.joinable() && bg_done_) background_.join();
  if (source_depth_ == 0) {  // a new line of the user's (not one of a sourced script)
    script_interrupted_ = false;
    last_error_code_ = 0;
  }
  // A script's errors are "FILE:LINE:COL: message" (INTERFACE.md), the column the parser's or
  // the command's; the shell's own, "error: message" (with the parser's column).
  int col = 0;
  if (const auto first = line.find_first_not_of(" \t"); first != std::string::npos) col = static_cast<int>(first) + 1;
  auto at = [&](int parse_col) {
    if (where.empty())
      return std::string("error: ") + (parse_col > 0 ? "column " + std::to_string(parse_col) + ": " : "");
    return where + ":" + std::to_string(std::max(1, parse_col > 0 ? parse_col : col)) + ": ";
  };
  int code = 2;
  try {
    if (const std::optional<Command> c = parse_line(line)) dispatch(*c);
    code = 0;
  } catch (const ParseError& e) {
    err_ << at(e.col) << e.what() << "\n";
  } catch (const RunFailure& e) {
    err_ << at(0) << e.what() << "\n";
    code = static_cast<int>(ExitCode::kNumerical);
  } catch (const IoError& e) {  // a file that cannot be read or written: exit 4, as `silt run`'s
    err_ << at(0) << e.what() << "\n";
    code = static_cast<int>(ExitCode::kIo);
  } catch (const std::exception& e) {  // SceneError and the commands' own errors
    err_ << at(0) << e.what() << "\n";
  }
  if (sim_ && !running()) shown_t_ = sim_->state().t;  // a running simulation publishes it itself
  if (code == 0) return true;
  err_ << std::flush;
  last_error_code_ = std::max(last_error_code_, code);
  return false;
}

void Session::dispatch(const Command& c) {
  static const std::vector<std::pair<std::string, Handler>> table = {
      {"load", &Session::cmd_load},       {"reload", &Session::cmd_reload},   {"check", &Session::cmd_check},
      {"run", &Session::cmd_run},         {"start", &Session::cmd_start},     {"stop", &Session::cmd_stop},
      {"wait", &Session::cmd_wait},       {"set", &Session::cmd_set},         {"get", &Session::cmd_get},
      {"params", &Session::cmd_params},   {"print", &Session::cmd_print},     {"watch", &Session::cmd_watch},
      {"stats", &Session::cmd_stats},     {"profile", &Session::cmd_profile}, {"render", &Session::cmd_render},
      {"frames", &Session::cmd_frames},   {"vtk", &Session::cmd_vtk},         {"save", &Session::cmd_save},
      {"restore", &Session::cmd_restore}, {"reset", &Session::cmd_reset},     {"hash", &Session::cmd_hash},
      {"freeze", &Session::cmd_freeze},   {"fields", &Session::cmd_fields},   {"field", &Session::cmd_field},
      {"source", &Session::cmd_source},   {"help", &Session::cmd_help},       {"quit", &Session::cmd_quit},
  };
  const CommandSpec& spec = check_command(c);
  for (const auto& [name, handler] : table)
    if (name == spec.name) return (this->*handler)(c);
}

State Session::compressed(const Model& m, const State* from) {
  PreparationReport rep;
  interrupt_ = false;
  State packed = prepare_packing(m, threads_, &rep, &interrupt_, from);
  interrupt_ = false;
  // A numerical failure, exit 3 in `silt play` as in `silt run` (it exited 2).
  if (rep.end == RunEnd::kFailed)
    throw RunFailure("the preparation (prepare.compress) failed: " + rep.failure +
                     (sim_ ? "; the scene and its state are as they were" : "; nothing was loaded"));
  out_ << "prepared: isotropic compression, " << rep.steps << " steps in " << rep.wall_s << " s"
       << (rep.end == RunEnd::kStatic ? ", static"
           : rep.reached_phi          ? ", at prepare.phi"
                                      : ", not static (prepare.max_steps or interrupted)")
       << "\n";
  return packed;
}

std::string Session::install(Model m, const std::optional<State>& keep) {
  auto next = std::make_unique<Simulation>(std::move(m), threads_);
  if (keep) {
    next->restore(*keep);
  } else if (next->model().prepare.compress) {
    next->restore(compressed(next->model(), nullptr));
  }
  // The state a run would start from (the forces of t = 0, the fluid's initial velocity, a paste's
  // connections and velocities): what `print`, `save` and `hash` show before the first step, as
  // `silt run --steps 0` shows it.
  next->prepare();
  if (keep && next->state().failure.failed) return next->state().failure.message;
  const bool same_series = keep && sim_ && next->model().observe == sim_->model().observe;
  sim_ = std::move(next);
  if (!keep) rewind_series(0);
  // The state kept with the same observables: its series goes on (samples, file and interval).
  // Else a new model starts a new series: a file the old one went to is closed as it is, not
  // overwritten.
  if (same_series) {
    rewatch();
    return "";
  }
  if (!stats_file_.empty()) {
    out_ << "stats file " << stats_file_ << " closed with " << stats_->rows().size() << " sample(s)\n";
    stats_file_.clear();
    stats_every_ = 0;
  }
  stats_.emplace("", sim_->model().observe);
  rewatch();
  return "";
}

void Session::rewind_series(int64_t step) {
  for (int64_t* last : {&frames_last_step_, &vtk_last_step_, &watch_.last_step})
    if (*last >= step) *last = step > 0 ? step - 1 : -1;
}

void Session::rewatch() {
  watch_.observer.reset();
  if (!watch_.names.empty()) {
    try {
      watch_.observer.emplace(sim_->model(), watch_.names);
    } catch (const std::exception& e) {
      out_ << "watch off: " << e.what() << "\n";
      watch_ = Watch{};
    }
  }
}

// Runs fn at the next step boundary of the background run, or now when nothing runs. Rethrows
// what fn throws, in the caller's thread.
//
// A request is queued only while bg_done_ is false, under the mutex; the run's last drain takes
// the queue and sets bg_done_ under the same lock (serve_requests). So a queued request is always
// served by the run, and the caller can simply wait for it: none is ever run twice or left queued.
void Session::at_boundary(const std::function<void()>& fn) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!(background_.joinable() && !bg_done_)) {
    lock.unlock();
    fn();
    return;
  }
  bool done = false;
  std::exception_ptr error;
  requests_.push_back([this, &fn, &done, &error] {
    try {
      fn();
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard<std::mutex> served(mutex_);
    done = true;
    cv_.notify_all();
  });
  has_requests_ = true;
  cv_.wait(lock, [&] { return done; });
  if (error) std::rethrow_exception(error);
}

// On the run's thread: runs the queued requests; `last` (the run has ended) also marks the run
// done in the same critical section, after which nothing is queued any more.
void Session::serve_requests(bool last) {
  std::deque<std::function<void()>> todo;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    todo.swap(requests_);
    has_requests_ = false;
    if (last) bg_done_ = true;
  }
  for (auto& f : todo) f();
}

RunOptions Session::run_options(const RunLength& len, bool background) {
  const std::string verb = background ? "start" : "run";  // (for messages)
  Simulation& s = sim();
  const Model& m = s.model();
  RunOptions opt;
  constexpr int64_t kForever = kMaxRunSteps;
  switch (len.kind) {
    case RunLength::kSteps: opt.steps = len.steps; break;
    case RunLength::kTime: {
      opt.time = len.time;
      // (steps_for says -1 beyond kMaxRunSteps)
      if (s.steps_for(opt) < 0)
        throw std::runtime_error(verb + " " + format_number(len.time) + "s: " + too_many_steps(m.dt));
      break;
    }
    case RunLength::kUntil: {
      opt.steps = kForever;
      if (until_never_holds(len.until, s.state().t, s.state().step))
        throw std::runtime_error(
            verb +
            " until: the condition can never hold: t and step only grow, and it asks them to be below where they "
            "are, above a value and below a smaller one, or a step that is not whole (now t = " +
            // (to 10 digits, past the 6 shown elsewhere and within the 1e-9 that t is taken to be at
            // a value: an adaptive step's t typed back as shown, and refused, looked at its value)
            format_number(s.state().t, 10) + m.unit("s") + ", step " + std::to_string(s.state().step) + ")");
      // (`run until t >= 1e300` ran until killed: as `run 1e300s`, refused)
      if (m.adaptive_dt) break;
      const double least = until_steps_at_least(len.until, s.state().t, s.state().step, m.dt);
      if (least > static_cast<double>(kMaxRunSteps))
        throw std::runtime_error(verb + " until: the condition cannot hold before " + format_number(least, 3) +
                                 " steps: " + too_many_steps(m.dt));
      if (least > static_cast<double>(kLongRunSteps))
        say("warning: the run takes at least " + format_number(least, 3) + " steps of dt = " + format_number(m.dt, 4) +
                m.unit("s") + " before its condition can hold",
            background);
      break;
    }
    case RunLength::kStatic:
      if (!m.box_control.on)
        throw std::runtime_error(
            "run until static: the equilibrium criterion (run.static_*) is relative to the imposed pressure, and this "
            "scene has no box.pressure");
      // (a cyclic scene's ran without end: 66,849 steps and on)
      if (m.box_control.cycle != StressCycle::kNone)
        throw std::runtime_error(
            "run until static: the imposed stresses cycle (box.cycle), and a packing under them is never at rest: "
            "give N, Ts or until EXPR");
      if (m.shear.on && !m.shear.stress_controlled && m.shear.rate != 0)
        throw std::runtime_error(
            "run until static: the imposed shear rate (shear.rate) keeps the packing flowing: set it to 0 first, or "
            "give N, Ts or until EXPR");
      opt.steps = kForever;
      opt.stop_when_static = true;
      break;
    case RunLength::kSteady:
      if (!has_steady_test(m))
        throw std::runtime_error(
            "run until steady: the steady-state test (run.steady_tol) is the fluid's, and this "
            "scene has no [fluid]");
      opt.steps = kForever;
      opt.stop_when_steady = true;
      break;
    case RunLength::kScene: {
      // To the scene's end from where the state is (its time, when it gives one: a step changed
      // since it was loaded does not move that end).
      const RunOptions left = s.scene_run_left();
      if (left.time < 0 && left.steps <= 0)
        throw std::runtime_error(m.gives_run_length()
                                     ? "the scene's run length is reached (" +
                                           (m.run_time >= 0 ? "t = " + format_number(m.run_time) + " s"
                                                            : "step " + std::to_string(m.run_steps)) +
                                           "): give N, Ts or until EXPR to go on"
                                     : "the scene gives no run length ([run] steps or time): give N, Ts or until EXPR");
      opt.steps = left.steps;
      opt.time = left.time;
      opt.stop_when_static = m.until_static.on;
      opt.stop_when_steady = m.stop_when_steady;
      break;
    }
  }
  // A fixed step that makes the run hundreds of millions of steps: said before it starts, as by
  // `silt run` (Ctrl-C pauses it).
  if (len.kind == RunLength::kSteps || len.kind == RunLength::kTime || len.kind == RunLength::kScene)
    if (const std::string w = s.long_run_note(opt); !w.empty()) say("warning: " + w, background);
  opt.interrupt = &interrupt_;
  opt.on_notice = [this, background](const std::string& n) { say("warning: " + n, background); };
  opt.boundary_wanted = [this] { return has_requests_.load(); };
  opt.between_steps = [this] {
    shown_t_ = sim_->state().t;
    if (has_requests_) serve_requests(false);
  };
  // A run calls every hook at its start (and at an end its length did not set): across runs an
  // output every N steps takes the state at its start only when it has none yet, and each step
  // once (twenty `run 1` wrote twenty-two frames, two of them the same step's).
  auto due = [](const State& st, int64_t every, int64_t& last) {
    const bool first = last < 0;
    if (st.step == last || (!first && st.step % every != 0)) return false;
    last = st.step;
    return true;
  };
  if (watch_.every > 0 && watch_.observer) {
    opt.hooks.push_back({watch_.every, [this, background, due](const State& st) {
                           if (!watch_.observer) return;  // `watch off` during the run (at a boundary)
                           if (!due(st, watch_.every, watch_.last_step)) return;
                           const auto v = watch_.observer->sample(sim_->model(), st);
                           std::string line = "step " + std::to_string(st.step) + ":";
                           for (size_t k = 0; k < v.size(); ++k)
                             line += "  " + watch_.names[k] + " = " + format_value(v[k], watch_.observer->units()[k]);
                           say(line, background);
                         }});
  }
  if (frames_ && frames_every_ > 0) {
    opt.hooks.push_back({frames_every_, [this, due](const State& st) {
                           if (!due(st, frames_every_, frames_last_step_)) return;
                           frames_->submit(render::build_render_scene(sim_->model(), st, sim_->model().render));
                         }});
  }
  if (vtk_ && vtk_every_ > 0) {
    opt.hooks.push_back({vtk_every_, [this, due](const State& st) {
                           if (!vtk_error_.empty() || !due(st, vtk_every_, vtk_last_step_)) return;
                           try {
                             vtk_->write(sim_->model(), st, module_grid_fields(sim_->model(), st));
                           } catch (const IoError& e) {
                             vtk_error_ = e.what();  // reported when the run ends
                           }
                         }});
  }
  if (len.kind == RunLength::kUntil) {
    // Each observable sampled once, however many clauses name it ("step >= 5 or step >= 10").
    std::vector<std::string> names;
    std::vector<size_t> column;  // clause k reads names[column[k]]
    bool cheap = true;
    std::vector<bool> of_last_step;  // clause k names a value of the last step
    for (const Clause& c : len.until.clauses) {
      const auto at = std::find(names.begin(), names.end(), c.observable);
      column.push_back(static_cast<size_t>(at - names.begin()));
      if (at == names.end()) names.push_back(c.observable);
      cheap = cheap && (c.observable == "t" || c.observable == "step" || c.observable == "dt");
      of_last_step.push_back(observable_of_last_step(c.observable, m));
    }
    auto obs = std::make_shared<Observer>(m, names);
    const Condition cond = len.until;
    // Cheap observables are tested at every step; the others every 10 steps, and in between where
    // a term's window of t and step closes before the next test (tested every 10 steps, "step == 7
    // or ke < 0" ran on; sampled at every step, "step == 20000 or z_star > 100" made the chute's
    // run 2.2 times as long). A condition that t and step have made impossible ends the run
    // ("t >= 0.001 and step == 90" ran on past step 90).
    constexpr int64_t kEvery = 10;
    const bool windows = !cheap && cond.has_window();
    // A value of the last step is none before the first: its clauses do not hold on a state no
    // step has made (`run until fluid.change_rate < 1e-3` held at step 0, where it reads 0), and the
    // others are tested there as always ("step >= 0 or fluid.cfl < 0.6" ran 10 steps).
    // The state a run starts from is tested too, at whatever step ("run 3" then "run until step >= 0
    // or fluid.cfl < 0.6" ran to step 10).
    const int64_t first = sim_->state().step;
    opt.hooks.push_back(
        {cheap || windows ? 1 : kEvery,
         [this, obs, cond, column, cheap, of_last_step, first, adaptive = m.adaptive_dt](const State& st) {
           const bool regular = cheap || st.step % kEvery == 0 || st.step == first;
           const bool sampled = regular || cond.window_closes(st.t, st.step, st.dt, kEvery - st.step % kEvery) ||
                                (adaptive && cond.time_window_open(st.t, st.step));
           if (sampled && cond.holds(obs->sample(sim_->model(), st), &column, st.step == 0 ? &of_last_step : nullptr)) {
             until_end_ = UntilEnd::kMet;
             interrupt_ = true;
           } else if (until_never_holds(cond, st.t, st.step)) {
             // (at every call, which costs no sample: "step == 45 and ke < 0" ran to step 50)
             until_end_ = UntilEnd::kNeverHolds;
             interrupt_ = true;
           }
         }});
  }
  return opt;
}

void Session::run_for(const RunLength& len, bool background) {
  Simulation& s = sim();
  if (s.state().failure.failed)
    throw std::runtime_error("the last run failed (" + s.state().failure.message +
                             "); restore a checkpoint, reset, or change the parameter and reset");
  if (len.kind == RunLength::kUntil)
    for (const Clause& c : len.until.clauses)
      if (const std::string err = check_observable(c.observable, s.model()); !err.empty()) throw ParseError(c.col, err);
  RunOptions opt = run_options(len, background);
  // Says how the run ended. After a failure the state goes back to the last good one (it can be
  // saved, or run again once the parameter is changed) and the failure's message is returned.
  auto report = [this](const RunReport& r, const RunJob& job, bool from_background) {
    const State& st = sim_->state();
    std::string how, failure;
    switch (r.end) {
      case RunEnd::kDone: how = "done"; break;
      case RunEnd::kStatic: how = "static"; break;
      case RunEnd::kSteady: how = "steady"; break;
      case RunEnd::kInterrupted:
        how = until_end_ == UntilEnd::kMet          ? "condition met"
              : until_end_ == UntilEnd::kNeverHolds ? "the condition can no longer hold (t and step only grow)"
                                                    : "paused";
        break;
      case RunEnd::kFailed: failure = st.failure.message; break;
    }
    // A foreground failure is the command's error (on err); a background one has only this line.
    if (!failure.empty()) how = from_background ? "failed: " + failure + "\n " : "failed after";
    std::string line = how + (failure.empty() ? ": " : " ") + std::to_string(r.steps_done) + " steps in " +
                       format_number(r.wall_s, 3) + " s";
    if (!failure.empty()) {
      sim_->restore(job.kept_state());  // (the last good state, which the job sampled)
      line += "; back to the last good state";
    }
    line += ", now t = " + format_number(st.t) + sim_->model().unit("s") + ", step " + std::to_string(st.step);
    say(line, from_background);
    return failure;
  };
  interrupt_ = false;
  until_end_ = UntilEnd::kNone;
  if (!background) {
    std::optional<cli::Progress> bar;
    if (progress_) {
      bar.emplace(true, s.state().step, opt.steps < std::numeric_limits<int64_t>::max() / 8 ? opt.steps : 0,
                  s.model().n_grains, s.model().n_cells());
      opt.on_progress = [&bar](const State& st) { bar->update(st); };
    }
    RunJobOptions jo;
    jo.series = &*stats_;
    jo.every = stats_every_;
    RunJob job(s, jo);
    const RunReport r = job.run(opt);
    if (bar) bar->finish();
    if (frames_) frames_->finish();
    // (an output's error is noted before a failure is thrown: it was lost then)
    note_output_errors();
    if (const std::string failure = report(r, job, false); !failure.empty()) throw RunFailure(failure);
    report_output_errors();
    return;
  }
  bg_done_ = false;
  background_started_ = true;
  background_waited_ = false;
  RunJobOptions jo;
  jo.series = &*stats_;
  jo.every = stats_every_;
  auto job = std::make_shared<RunJob>(*sim_, jo);
  background_ = std::thread([this, opt, report, job] {
    const RunReport r = job->run(opt);
    if (const std::string failure = report(r, *job, true); !failure.empty()) {
      std::lock_guard<std::mutex> lock(mutex_);
      background_failure_ = failure;
    }
    if (frames_) frames_->finish();
    if (const std::string fresh = note_output_errors(); !fresh.empty()) say(fresh, true);
    shown_t_ = sim_->state().t;
    background_end_step_ = sim_->state().step;  // read after the join
    background_interrupted_ =
        r.end == RunEnd::kInterrupted && until_end_ == UntilEnd::kNone;  // (an `until` ends so too)
    serve_requests(true);  // the requests that came after the last step; no more after these
  });
  say("running in the background (stop pauses it)", false);
}

}  // namespace silt::shell
