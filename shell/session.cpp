// Session: loading, running (foreground and background), and the step-boundary machinery.
// The commands that only read or change things are in session_commands.cpp.
#include "shell/session.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <sstream>

#include "shell/progress.hpp"
#include "silt/observables.hpp"

namespace silt::shell {

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

void Session::interrupt() { interrupt_ = true; }

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
  std::snprintf(buf, sizeof buf, "silt[t=%.4g%s]> ", sim_->state().t, running() ? " running" : "");
  return buf;
}

bool Session::execute(const std::string& line, const std::string& where) {
  // Reap a background run that ended by itself.
  if (background_.joinable() && bg_done_) background_.join();
  try {
    const std::optional<Command> c = parse_line(line);
    if (!c) return true;
    dispatch(*c);
    return true;
  } catch (const ParseError& e) {
    err_ << (where.empty() ? std::string("error") : where) << ": "
         << (e.col > 0 && where.empty() ? "column " + std::to_string(e.col) + ": " : std::string()) << e.what() << "\n";
  } catch (const SceneError& e) {
    err_ << (where.empty() ? std::string("error") : where) << ": " << e.what() << "\n";
  } catch (const std::exception& e) {
    err_ << (where.empty() ? std::string("error") : where) << ": " << e.what() << "\n";
  }
  err_ << std::flush;
  return false;
}

void Session::dispatch(const Command& c) {
  static const std::vector<std::pair<std::string, Handler>> table = {
      {"load", &Session::cmd_load},       {"reload", &Session::cmd_reload},   {"check", &Session::cmd_check},
      {"run", &Session::cmd_run},         {"start", &Session::cmd_start},     {"stop", &Session::cmd_stop},
      {"set", &Session::cmd_set},         {"get", &Session::cmd_get},         {"params", &Session::cmd_params},
      {"print", &Session::cmd_print},     {"watch", &Session::cmd_watch},     {"stats", &Session::cmd_stats},
      {"profile", &Session::cmd_profile}, {"render", &Session::cmd_render},   {"frames", &Session::cmd_frames},
      {"save", &Session::cmd_save},       {"restore", &Session::cmd_restore}, {"reset", &Session::cmd_reset},
      {"source", &Session::cmd_source},   {"help", &Session::cmd_help},       {"quit", &Session::cmd_quit},
  };
  const CommandSpec& spec = check_command(c);
  for (const auto& [name, handler] : table)
    if (name == spec.name) return (this->*handler)(c);
}

void Session::install(Model m, const std::optional<State>& keep) {
  auto next = std::make_unique<Simulation>(std::move(m), threads_);
  if (keep) {
    next->restore(*keep);
  } else if (next->model().prepare.compress) {
    PreparationReport rep;
    interrupt_ = false;
    next->restore(prepare_packing(next->model(), threads_, &rep, &interrupt_));
    out_ << "prepared: isotropic compression, " << rep.steps << " steps in " << rep.wall_s << " s"
         << (rep.end == RunEnd::kStatic ? ", static" : ", not static (prepare.max_steps or interrupted)") << "\n";
    interrupt_ = false;
  }
  sim_ = std::move(next);
  stats_.emplace("", sim_->model().observe);
  stats_observer_.emplace(sim_->model(), sim_->model().observe);
  watch_.observer.reset();
  if (!watch_.names.empty()) {
    try {
      watch_.observer.emplace(sim_->model(), watch_.names);
    } catch (const std::exception&) {
      watch_ = Watch{};
    }
  }
}

// Runs fn at the next step boundary of the background run, or now when nothing runs. Rethrows
// what fn throws, in the caller's thread.
void Session::at_boundary(const std::function<void()>& fn) {
  if (!(background_.joinable() && !bg_done_)) {
    fn();
    return;
  }
  auto done = std::make_shared<bool>(false);
  auto error = std::make_shared<std::exception_ptr>();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    requests_.push_back([fn, done, error] {
      try {
        fn();
      } catch (...) {
        *error = std::current_exception();
      }
      *done = true;
    });
    has_requests_ = true;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return *done || bg_done_.load(); });
  if (!*done) {  // the run ended before serving us: the simulation is free now
    lock.unlock();
    fn();
    return;
  }
  if (*error) std::rethrow_exception(*error);
}

std::vector<double> Session::observe_now(const std::vector<std::string>& names) {
  const Observer obs(sim().model(), names);  // throws std::invalid_argument with a suggestion
  std::vector<double> values;
  at_boundary([&] { values = obs.sample(sim_->model(), sim_->state()); });
  return values;
}

RunOptions Session::run_options(const RunLength& len, bool background) {
  Simulation& s = sim();
  const Model& m = s.model();
  RunOptions opt;
  constexpr int64_t kForever = std::numeric_limits<int64_t>::max() / 4;
  switch (len.kind) {
    case RunLength::kSteps: opt.steps = len.steps; break;
    case RunLength::kTime: opt.steps = static_cast<int64_t>(std::ceil(len.time / m.dt - 1e-9)); break;
    case RunLength::kUntil: opt.steps = kForever; break;
  }
  opt.interrupt = &interrupt_;
  opt.boundary_wanted = [this] { return has_requests_.load(); };
  opt.between_steps = [this] {
    if (!has_requests_) return;
    std::deque<std::function<void()>> todo;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      todo.swap(requests_);
      has_requests_ = false;
    }
    for (auto& f : todo) f();
    cv_.notify_all();
  };
  opt.hooks.push_back({m.sample_every, [this](const State& st) {
                         if (stats_) stats_->add(stats_observer_->sample(sim_->model(), st), st.t);
                       }});
  if (watch_.every > 0 && watch_.observer) {
    opt.hooks.push_back({watch_.every, [this, background](const State& st) {
                           const auto v = watch_.observer->sample(sim_->model(), st);
                           std::ostringstream o;
                           o.precision(6);
                           o << "step " << st.step << ":";
                           for (size_t k = 0; k < v.size(); ++k) o << "  " << watch_.names[k] << " = " << v[k];
                           say(o.str(), background);
                         }});
  }
  if (frames_ && frames_every_ > 0) {
    opt.hooks.push_back({frames_every_, [this](const State& st) {
                           frames_->submit(render::build_render_scene(sim_->model(), st, sim_->model().render));
                         }});
  }
  if (len.kind == RunLength::kUntil) {
    std::vector<std::string> names;
    bool cheap = true;
    for (const Clause& c : len.until.clauses) {
      names.push_back(c.observable);
      cheap = cheap && (c.observable == "t" || c.observable == "step" || c.observable == "dt");
    }
    auto obs = std::make_shared<Observer>(m, names);
    const Condition cond = len.until;
    // Cheap observables are tested at every step; the others every 10 steps.
    opt.hooks.push_back({cheap ? 1 : 10, [this, obs, cond](const State& st) {
                           if (cond.holds(obs->sample(sim_->model(), st))) {
                             until_met_ = true;
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
      if (const std::string err = check_observable(c.observable, s.model()); !err.empty()) throw std::runtime_error(err);
  RunOptions opt = run_options(len, background);
  auto report = [this](const RunReport& r, bool from_background) {
    const State& st = sim_->state();
    std::ostringstream o;
    o.precision(6);
    switch (r.end) {
      case RunEnd::kDone: o << "done"; break;
      case RunEnd::kStatic: o << "static"; break;
      case RunEnd::kInterrupted: o << (until_met_ ? "condition met" : "paused"); break;
      case RunEnd::kFailed: o << "failed: " << st.failure.message; break;
    }
    o << (r.end == RunEnd::kFailed ? "\n  " : ": ") << r.steps_done << " steps in " << r.wall_s << " s";
    if (r.end == RunEnd::kFailed) {
      // Keep the last good state: it can be saved, or run again after changing the parameter.
      sim_->restore(sim_->last_good_state());
      o << "; back to the last good state";
    }
    o << ", now t = " << st.t << " s, step " << st.step;
    say(o.str(), from_background);
  };
  interrupt_ = false;
  until_met_ = false;
  if (!background) {
    std::optional<cli::Progress> bar;
    if (progress_) {
      bar.emplace(true, s.state().step, opt.steps < std::numeric_limits<int64_t>::max() / 8 ? opt.steps : 0, s.model().n_grains);
      opt.on_progress = [&bar](const State& st) { bar->update(st); };
    }
    const RunReport r = s.run(opt);
    if (bar) bar->finish();
    if (frames_) frames_->finish();
    report(r, false);
    return;
  }
  bg_done_ = false;
  background_ = std::thread([this, opt, report] {
    const RunReport r = sim_->run(opt);
    {
      // Serve requests that came after the last step.
      std::deque<std::function<void()>> todo;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        todo.swap(requests_);
        has_requests_ = false;
      }
      for (auto& f : todo) f();
    }
    report(r, true);
    bg_done_ = true;
    cv_.notify_all();
  });
  say("running in the background (stop pauses it)", false);
}

}  // namespace silt::shell
