// The shell's commands (the run machinery is in session.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>

#include "shell/session.hpp"
#include "shell/table.hpp"
#include "silt/input_files.hpp"
#include "silt/io.hpp"
#include "silt/module.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/text.hpp"

namespace silt::shell {
namespace {

// A string key's choices, as its range: "linear hertz hooke".
std::string join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

// Each word an observable of the model, or its error at that word (it was at the command's).
void check_observable_words(const std::vector<Token>& words, const Model& m) {
  for (size_t k = 0; k < words.size(); ++k) {
    const Token& t = words[k];
    if (const std::string err = check_observable(t.text, m); !err.empty()) throw ParseError(t.col, err);
    for (size_t j = 0; j < k; ++j)
      if (words[j].text == t.text) throw ParseError(t.col, "'" + t.text + "' is listed twice");
  }
}

}  // namespace

void Session::cmd_load(const Command& c) {
  require_stopped("cannot load a scene");
  const std::string file = input_path(c.args[0].text);
  SceneDesc read = load_scene_file(file);
  // (compiled from a copy, which it marks with the keys it uses)
  Model m = compile(SceneDesc(read));   // throws: the previous scene stays
  install(std::move(m), std::nullopt);  // throws (a preparation that fails): the same
  scene_file_ = file;
  scene_read_ = std::move(read);
  overrides_.clear();
  const Model& model = sim_->model();
  out_ << "loaded " << file << ": " << model.n_grains << " grains (" << model.dim << "D), "
       << (model.adaptive_dt ? step_text(model) : "dt = " + format_number(model.dt) + (model.reduced_units ? "" : " s"))
       << ", " << model.walls.size() << " wall(s)\n";
}

void Session::cmd_reload(const Command&) {
  require_stopped("cannot reload");
  if (scene_file_.empty()) throw std::runtime_error("no scene loaded (load FILE)");
  SceneDesc read = load_scene_file(scene_file_);  // (the file as it is now)
  install(compile(scene_with(overrides_, &read)), std::nullopt);
  scene_read_ = std::move(read);
  out_ << "reloaded " << scene_file_ << " at t = 0";
  // (the values set were kept without a word: `get` then read them, not the file's)
  if (!overrides_.empty()) {
    out_ << ", with the value(s) set since it was loaded:";
    for (const Override& o : overrides_) out_ << " " << o.key << " = " << shown_word(o.value);
    out_ << " (load FILE reads the file alone)";
  }
  out_ << "\n";
}

void Session::cmd_check(const Command&) {
  Simulation& s = sim();
  out_ << describe(s.model()) << "step graph\n" << s.describe_graph();
}

namespace {

RunLength length_of(const Command& c) {
  if (!c.args.empty()) return parse_run_length(c.args);
  RunLength scene;
  scene.kind = RunLength::kScene;
  return scene;
}

}  // namespace

void Session::cmd_run(const Command& c) {
  require_stopped("cannot run");
  run_for(length_of(c), false);
}

void Session::cmd_start(const Command& c) {
  if (running()) throw std::runtime_error("already running (stop pauses it)");
  if (background_.joinable()) background_.join();
  run_for(length_of(c), true);
}

// A finite `start` may end before its `stop`: that is said, not an error, so that what a script
// does does not depend on how fast the machine is.
void Session::cmd_stop(const Command&) {
  // (`start N`, `wait`, `stop` failed a script: "nothing is running")
  if (!background_started_ && background_waited_) {
    background_waited_ = false;
    out_ << "the run had already ended at step " << background_end_step_ << " (wait)\n";
    return;
  }
  if (!background_started_) throw std::runtime_error("nothing is running");
  background_started_ = false;
  const bool ended = !running();
  interrupt_ = true;
  if (background_.joinable()) background_.join();
  for (const std::string& m : take_messages()) out_ << m << "\n";
  if (ended)
    out_ << (background_interrupted_ ? "the run had already been paused (interrupted) at step "
                                     : "the run had already ended at step ")
         << background_end_step_ << "\n";
}

void Session::cmd_wait(const Command&) {
  if (!background_started_) throw std::runtime_error("nothing is running");
  background_started_ = false;
  background_waited_ = true;
  if (background_.joinable()) background_.join();
  for (const std::string& m : take_messages()) out_ << m << "\n";
}

void Session::cmd_get(const Command& c) {
  const SceneDesc& d = sim().model().desc;
  const std::string key = canonical_key(c.args[0].text);
  const KeySpec* spec = find_key_spec(normalise_key(key));
  if (!spec) {
    throw std::runtime_error(unknown_key_message(key));
  }
  // (grains.5.count of a scene with one [[grains]] answered "(not set)")
  if (const std::string missing = d.missing_entry(key); !missing.empty()) throw std::runtime_error(missing);
  std::string value = "(not set)";
  if (auto it = d.entries.find(key); it != d.entries.end()) value = value_to_string(it->second.value);
  else if (const std::string chosen = spec->computed ? spec->computed(sim().model()) : std::string(); !chosen.empty())
    value = "(not set), computed " + chosen;
  else if (spec->def) value = value_to_string(*spec->def) + " (default)";
  const std::string unit = key_unit(*spec, sim().model());
  out_ << key << " = " << value << (unit.empty() ? "" : " " + unit) << "\n";
}

void Session::cmd_params(const Command& c) {
  const std::string prefix = c.args.empty() ? "" : canonical_key(c.args[0].text);
  Table t({"key", "value", "unit", "range", "live"});
  const SceneDesc& desc = sim_ ? sim_->model().desc : kNoScene;
  for (auto [key, value] : scene_parameters(desc)) {
    if (key.rfind(prefix, 0) != 0) continue;
    const KeySpec* spec = find_key_spec(key);
    // What the scene gave, else what compile() chose, else the schema's default.
    if (!desc.has(key)) {
      const std::string chosen = sim_ && spec->computed ? spec->computed(sim_->model()) : std::string();
      if (!chosen.empty()) value = chosen + " (computed)";
      else if (!value.empty()) value += " (default)";
    }
    const bool numeric =
        spec->type == KeyType::kInt || spec->type == KeyType::kReal || spec->type == KeyType::kRealList;
    t.add({key, value.empty() ? "-" : value, sim_ ? key_unit(*spec, sim_->model()) : spec->unit,
           numeric ? spec->range.str() : join_words(spec->choices), spec->steerable ? "yes" : ""});
  }
  if (t.rows() == 0) throw std::runtime_error("no key starts with '" + prefix + "'");
  t.print(out_);
}

void Session::cmd_print(const Command& c) {
  std::vector<std::string> names;
  const std::vector<Token> words = expand_lists(c.args);
  check_observable_words(words, sim().model());
  for (const Token& t : words) names.push_back(t.text);
  std::optional<Observer> obs;
  try {
    obs.emplace(sim().model(), names);
  } catch (const std::invalid_argument& e) {  // the bad name, with a suggestion
    throw std::runtime_error(e.what());
  }
  std::vector<double> values;
  at_boundary([&] { sim_->within([&] { values = obs->sample(sim_->model(), sim_->state()); }); });
  size_t w = 0;
  for (const auto& n : names) w = std::max(w, n.size());
  for (size_t k = 0; k < names.size(); ++k)
    out_ << std::left << std::setw(static_cast<int>(w)) << names[k] << " = " << format_value(values[k], obs->units()[k])
         << "\n";
}

void Session::cmd_watch(const Command& c) {
  if (c.args.size() == 1 && c.args[0].text == "off") {
    at_boundary([&] { watch_ = Watch{}; });  // a background run's hook reads it at its boundaries
    out_ << "watch off\n";
    return;
  }
  const size_t n = c.args.size();
  if (n < 3 || c.args[n - 2].text != "every") throw ParseError(c.name_col, "usage: watch OBS... every N | watch off");
  const int64_t every = parse_every(c.args[n - 1]);
  Watch w;
  std::vector<Token> words;
  for (size_t k = 0; k + 2 < n; ++k)
    for (const Token& t : expand_list(c.args[k])) words.push_back(t);
  check_observable_words(words, sim().model());
  for (const Token& t : words) w.names.push_back(t.text);
  try {
    w.observer.emplace(sim().model(), w.names);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  require_stopped("cannot change the watch");
  w.every = every;
  watch_ = std::move(w);
  out_ << "watching every " << watch_.every << " steps\n";
}

void Session::cmd_profile(const Command&) {
  Profile::Map prof;
  at_boundary([&] {
    if (sim_) prof = sim_->state().profile.stages();
  });
  sim();
  double total = 0;
  for (const auto& [name, st] : prof) total += st.seconds();
  if (total == 0) throw std::runtime_error("no step yet (run first)");
  std::vector<std::pair<std::string, StageTime>> order(prof.begin(), prof.end());
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& a, const auto& b) { return a.second.seconds() > b.second.seconds(); });
  Table t({"stage", "seconds", "calls", "us/call", "share"}, {false, true, true, true, true});
  for (const auto& [name, st] : order)
    t.add({name, fixed(st.seconds(), 3), std::to_string(st.calls),
           format_number(st.calls ? 1e6 * st.seconds() / st.calls : 0.0, 3),
           fixed(100 * st.seconds() / total, 1) + " %"});
  t.add({"total", fixed(total, 3), "", "", "100.0 %"});
  t.print(out_);
}

void Session::cmd_render(const Command& c) {
  Simulation& s = sim();
  render::View v = s.model().render;
  // (a .jpg got PNG data under its name)
  if (const std::string ext = std::filesystem::path(c.args[0].text).extension().string();
      ext != ".png" && ext != ".PNG")
    throw ParseError(c.args[0].col, "render writes PNG images: give a file name ending in .png");
  const std::vector<Token> args = expand_lists(c.args, 1);  // render a.png grains chains, or ["grains","chains"]
  if (args.size() == 1 && c.args.size() > 1)                // (it drew the scene's list)
    throw ParseError(c.args[1].col,
                     "an empty list draws nothing: give what to draw, or nothing for render.draw's list");
  if (args.size() > 1) {
    v.draw.clear();
    const KeySpec* spec = find_key_spec("render.draw");
    for (size_t k = 1; k < args.size(); ++k) {
      const std::string& item = args[k].text;
      if (std::find(spec->choices.begin(), spec->choices.end(), item) == spec->choices.end()) {
        std::string all;  // the key's own list
        for (const std::string& choice : spec->choices) all += (all.empty() ? "" : " ") + choice;
        throw ParseError(args[k].col, "'" + item + "' is not something to draw (" + all + ")");
      }
      // (a fluid's frame drew 'lubrication' as nothing, which render.draw refuses)
      if (const std::string why = draw_refusal(s.model(), item); !why.empty()) throw ParseError(args[k].col, why);
      v.draw.push_back(item);
    }
  }
  // (before drawing; a missing directory said only "cannot write", after the drawing)
  check_not_open_file(c.args[0].text, "image");
  check_not_restored(c.args[0].text, "image");
  check_output_path(c.args[0].text, "image");
  render::RenderScene rs;
  at_boundary([&] { rs = render::build_render_scene(s.model(), s.state(), v); });
  if (!raster_) raster_ = std::make_unique<render::Rasterizer>();
  render::Image img = raster_->draw(rs);
  render::compose_overlays(rs, img);
  render::write_png(c.args[0].text, img);
  out_ << "wrote " << c.args[0].text << " (" << img.width << " x " << img.height << ")\n";
  for (const std::string& w : rs.warnings) out_ << "warning: " << w << "\n";
}

void Session::check_not_open_file(const std::string& path, const std::string& what) const {
  check_not_inputs(path, what);
  if (const std::string clash = output_clash(path, stats_file_); !clash.empty())
    throw IoError("cannot write " + what + " '" + path + "': it and the stats file being written, " + stats_file_ +
                  ", are " + clash + "; `stats off` first");
  check_not_series_file(path, what);
}

void Session::set_script(const std::string& path) { scripts_ = {path}; }

void Session::check_not_inputs(const std::string& path, const std::string& what) const {
  if (sim_)
    for (const auto& [file, is] : sim_->model().files_read()) check_not_input(path, file, what, is);
  for (const std::string& script : scripts_) check_not_input(path, script, what, "a script being played");
}

void Session::check_not_restored(const std::string& path, const std::string& what) const {
  for (const std::string& c : restored_) check_not_input(path, c, what, "a checkpoint restored in this session");
}

void Session::check_not_series_file(const std::string& path, const std::string& what) const {
  if (frames_ && render::FrameWriter::owns(path, frames_dir_))
    throw IoError("cannot write " + what + " '" + path + "': it is a frame's name in " + frames_dir_ +
                  ", where the frames go; `frames off` first or another name");
  if (vtk_ && VtkWriter::owns(path, vtk_dir_))
    throw IoError("cannot write " + what + " '" + path + "': it is a VTK file's name in " + vtk_dir_ +
                  ", where the VTK files go; `vtk off` first or another name");
}

void Session::cmd_save(const Command& c) {
  Simulation& s = sim();
  State copy;
  check_not_open_file(c.args[0].text, "checkpoint");
  at_boundary([&] { copy = s.state(); });
  write_checkpoint(c.args[0].text, s.model(), copy);
  out_ << "saved step " << copy.step << " (t = " << format_number(copy.t) << s.model().unit("s") << ") to "
       << c.args[0].text << "\n";
}

void Session::cmd_hash(const Command&) {
  sim();
  uint64_t hash = 0;
  int64_t step = 0;
  at_boundary([&] {
    hash = state_hash(sim_->state());
    step = sim_->state().step;
  });
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  out_ << "state hash " << hex << " at step " << step << "\n";
}

void Session::cmd_restore(const Command& c) {
  require_stopped("cannot restore");
  Simulation& s = sim();
  std::vector<std::string> differences;  // run parameters other than the checkpoint's: allowed, shown
  const std::string file = input_path(c.args[0].text);
  std::vector<uint8_t> frozen;  // grains the checkpoint's session froze (`freeze`), frozen here too
  State st = read_checkpoint(file, s.model(), &differences, &frozen);
  // A compression's last good state (a failed preparation's in `silt run`) is compressed on, as
  // `silt run --restore` does, not run as it is.
  if (in_compression(st) && !s.model().prepare.compress)
    throw std::runtime_error("restore " + file + ": a compression's state before its end (step " +
                             std::to_string(st.step) +
                             "), and this scene prepares none: set prepare.compress true to go on compressing it");
  // (a compression holds no frozen grains: refused before the model takes them, which a failed
  // compression would have left frozen over a state where they are free)
  if (in_compression(st) && std::find(frozen.begin(), frozen.end(), 1) != frozen.end())
    throw std::runtime_error("restore " + file + ": a compression's state with grains frozen by freeze");
  if (const int64_t n = s.freeze_grains(frozen); n > 0)
    out_ << n << " grain(s) frozen in " << file << " (by freeze) are frozen here too\n";
  if (in_compression(st)) {
    out_ << "going on with the compression of " << file << " from its step " << st.step << "\n";
    st = compressed(s.model(), &st);
  }
  if (std::find(restored_.begin(), restored_.end(), file) == restored_.end()) restored_.push_back(file);
  s.restore(std::move(st));
  s.prepare();  // a checkpoint of a state never stepped (a fresh paste's): as install() does
  rewind_series(s.state().step);
  out_ << "restored step " << s.state().step << " (t = " << format_number(s.state().t) << s.model().unit("s") << ")";
  if (const size_t n = stats_->drop_after(s.state().t, s.state().step); n > 0)
    out_ << "; " << n << " sample(s) after it dropped from the stats"
         << (stats_file_.empty() ? "" : " (the file keeps them)");
  out_ << "\n";
  for (const std::string& d : differences) out_ << "warning: " << d << "\n";
}

void Session::cmd_reset(const Command&) {
  require_stopped("cannot reset");
  install(sim().model(), std::nullopt);  // (a new state: the cycles start again too)
  out_ << "back to t = 0\n";
}

void Session::cmd_source(const Command& c) {
  if (source_depth_ >= 16) throw std::runtime_error("source nested too deeply (16)");
  const std::string file = input_path(c.args[0].text);
  check_input_file(file, "script", kMaxTextFileBytes);
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read '" + file + "'");
  // The script's own relative files are found beside it, as in `silt play`.
  scripts_.push_back(file);
  ++source_depth_;
  std::string line;
  int n = 0, failures = 0, first_failure = 0;
  // Ctrl-C pauses the run in progress and abandons the script (and those that sourced it). An
  // error stops it, unless `silt play --keep-going` (which stopped at a sourced script's first).
  while ((failures == 0 || keep_going_) && !quit_ && !script_interrupted_ && std::getline(in, line)) {
    ++n;
    line = script_line(line, n);
    if (const auto start = line.find_first_not_of(" \t");
        echo_sources_ && start != std::string::npos && line[start] != '#')
      out_ << file << ":" << n << "> " << printable_line(line.substr(start)) << "\n";
    if (!execute(line, file + ":" + std::to_string(n)) && failures++ == 0) first_failure = n;
  }
  --source_depth_;
  scripts_.pop_back();
  if (script_interrupted_) throw std::runtime_error("source " + file + " interrupted at line " + std::to_string(n));
  if (failures > 0 && !keep_going_)
    throw std::runtime_error("source " + file + " stopped at line " + std::to_string(first_failure));
  if (failures > 0)
    throw std::runtime_error("source " + file + ": " + std::to_string(failures) + " line(s) failed, the first " +
                             std::to_string(first_failure));
}

void Session::cmd_help(const Command& c) {
  if (c.args.empty()) {
    Table t({"command", "what"});
    for (const CommandSpec& s : command_specs()) t.add({s.usage, s.summary});
    t.print(out_);
    // The observables (print, watch, run until, stats): those of the loaded scene's modules.
    out_ << "\nobservables" << (sim_ ? " of this scene" : "")
         << " (A, B: an axis x, y, z; W: a rotation axis, z only in 2D; K: an index)\n";
    Table o({"observable", "unit", "what"});
    const std::vector<ObservableDoc> docs = observable_docs(sim_ ? &sim_->model() : nullptr);
    // Every module's, before a scene is loaded: a name that more than one module defines (the
    // paste's and the fluid's solver.iters) says whose each line is.
    std::map<std::string, int> uses;
    for (const ObservableDoc& d : docs) ++uses[d.name];
    for (const ObservableDoc& d : docs)
      o.add({d.name, d.unit.empty() ? "-" : d.unit, (uses[d.name] > 1 ? d.module + ": " : std::string()) + d.doc});
    o.print(out_);
    out_ << "help COMMAND explains one; params lists the scene keys with their units and ranges\n";
    return;
  }
  const CommandSpec* s = find_command(c.args[0].text);
  if (!s) {
    std::string msg = "unknown command '" + c.args[0].text + "'";
    if (const std::string hint = suggest_command(c.args[0].text); !hint.empty())
      msg += "; did you mean '" + hint + "'?";
    throw std::runtime_error(msg);
  }
  out_ << s->usage << "\n  " << s->help << "\n";
}

void Session::cmd_quit(const Command&) {
  if (background_.joinable()) {
    interrupt_ = true;
    background_.join();
  }
  // (the run's end, "paused: N steps ...": the piped shell left without it)
  for (const std::string& m : take_messages()) out_ << m << "\n";
  quit_ = true;
}

}  // namespace silt::shell
