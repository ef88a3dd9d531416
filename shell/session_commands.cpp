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
#include "silt/module.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt::shell {
namespace {

// A string key's choices, as its range: "linear hertz hooke".
std::string join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

// The values compile() chose for keys the scene does not give (fluid.viscosity from
// fluid.reynolds, neighbor.skin, ...), but the run's length and step (said on their own).
std::vector<std::pair<std::string, std::string>> computed_values(const Model& m) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [key, given] : scene_parameters(m.desc)) {  // (the keys `params` shows)
    const KeySpec* k = find_key_spec(key);
    if (k->computed && key.rfind("run.", 0) != 0 && !m.desc.has(key))
      if (std::string v = k->computed(m); !v.empty()) out.emplace_back(key, std::move(v));
  }
  return out;
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
       << (model.adaptive_dt ? "adaptive time step"
                             : "dt = " + format_number(model.dt) + (model.reduced_units ? "" : " s"))
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

namespace {

// Whether a steerable key can change the dry compression that prepares a packing
// (prepare.compress): not the keys of what the compression leaves out (the liquid, the shear, the
// cycles) nor those of the output.
const char* const kPreparationKept =
    "note: the packing compressed at load is kept; `reset` compresses it again under this value, as `silt run "
    "--set` does\n";

bool enters_preparation(const std::string& key) {
  // (the lubrication's range sets the neighbour list's, whose pairs the packing carries: the
  // shell's kept packing and `silt run --set` parted by 1e-8 at their first solve)
  if (key == "lubrication.h_max_over_a") return true;
  for (const char* p : {"lubrication.", "shear.", "box.cycle", "output.", "render."})
    if (key.rfind(p, 0) == 0) return false;
  return true;
}

}  // namespace

void Session::cmd_set(const Command& c) {
  Simulation& s = sim();
  // KEY VALUE, or several pairs taken as one change: values valid only together (a fluid's domain
  // and its cells, whose spacing must be the same along every axis) could not be set one at a time.
  if (c.args.size() % 2 != 0)
    throw std::runtime_error("set takes KEY VALUE pairs: '" + c.args.back().text + "' has no value");
  std::vector<Override> changes;
  std::string typed = "set";  // (as typed, for messages)
  for (size_t k = 0; k < c.args.size(); k += 2) {
    changes.push_back({canonical_key(c.args[k].text), c.args[k + 1].text});
    if (!find_key_spec(normalise_key(changes.back().key)))
      throw std::runtime_error(unknown_key_message(changes.back().key));
    // (a key and one it is an alternative to: the last had replaced the first, unsaid, where a
    // scene file giving both is refused)
    const std::vector<std::string> others = alternatives_of(changes.back().key);
    for (size_t j = 0; j + 1 < changes.size(); ++j) {
      if (changes[j].key == changes.back().key)
        throw std::runtime_error("set: '" + changes.back().key + "' is given twice");
      if (std::find(others.begin(), others.end(), changes[j].key) != others.end())
        throw std::runtime_error("set: '" + changes[j].key + "' and '" + changes.back().key +
                                 "' are alternatives: give one of them");
    }
    typed += " " + changes.back().key + " " + shown_word(c.args[k + 1].text);
  }
  const Override& change = changes.front();
  const bool several = changes.size() > 1;
  const KeySpec* spec = find_key_spec(normalise_key(change.key));
  // The changes typed so far, with these last (each replacing an earlier value of its key, and
  // the values of the keys it is an alternative to: fluid.reynolds replaces fluid.viscosity).
  std::vector<Override> next = overrides_;
  std::vector<std::string> replaced;
  for (const Override& o : changes)
    for (const std::string& k : alternatives_of(o.key)) replaced.push_back(k);
  const auto replaced_by = [&](const std::string& key) {
    return std::find(replaced.begin(), replaced.end(), key) != replaced.end();
  };
  const auto typed_now = [&](const std::string& key) {
    return std::any_of(changes.begin(), changes.end(), [&](const Override& o) { return o.key == key; });
  };
  next.erase(std::remove_if(next.begin(), next.end(),
                            [&](const Override& o) { return typed_now(o.key) || replaced_by(o.key); }),
             next.end());
  next.insert(next.end(), changes.begin(), changes.end());
  // A fixed step that another key changes: said (fluid.reynolds over a scene's fluid.viscosity makes
  // its fluid.dt read in units of L / U, and a channel's step doubled without a word).
  const bool was_fixed = !s.model().adaptive_dt;
  const double dt_was = s.model().dt;
  const auto computed_was = computed_values(s.model());
  const auto note_step = [&] {
    const Model& m = sim().model();  // (a recompile installs another simulation than `s`)
    // A value computed from the one set, changed with it (a lid's speed set in a scene given by
    // fluid.reynolds changed the viscosity, and the shell said only the speed).
    for (const auto& now : computed_values(m)) {
      const std::string& key = now.first;
      const std::string& value = now.second;
      const auto was =
          std::find_if(computed_was.begin(), computed_was.end(), [&](const auto& kv) { return kv.first == key; });
      if (was == computed_was.end() || was->second == value || typed_now(key) || replaced_by(key)) continue;
      const std::string unit = key_unit(*find_key_spec(key), m);
      out_ << "note: " << key << " is now " << value << (unit.empty() ? "" : " " + unit) << " (it was " << was->second
           << "), computed from the scene as it now reads\n";
    }
    // (not for the key that sets the step, nor its alternative: run.dt_over_tc is run.dt's)
    const std::vector<std::string> sets_step = alternatives_of(m.dt_key);
    const bool step_typed = typed_now(m.dt_key) || std::any_of(sets_step.begin(), sets_step.end(), typed_now);
    if (was_fixed && !m.adaptive_dt && m.dt != dt_was && !step_typed)
      out_ << "note: the time step is now " << format_number(m.dt) << m.unit("s") << " (it was "
           << format_number(dt_was) << m.unit("s") << "), "
           << (m.dt_key == "run.dt" && !m.desc.has("run.dt")
                   ? std::string("the default step (0.02 t_c) of the scene as it now reads")
                   : "from " + m.dt_key + " as the scene now reads it")
           << "\n";
  };
  const auto preparation_note = [&](const State& st) {
    if (st.step == 0 && sim().model().prepare.compress &&
        std::any_of(changes.begin(), changes.end(), [](const Override& o) { return enters_preparation(o.key); }))
      out_ << kPreparationKept;
  };
  if (spec->steerable && !several) {
    // The scene as the file and the values typed make it: a key's alternatives come back from the
    // file when it replaces the value that had replaced them (`set gravity.vector V` then `set
    // gravity.magnitude G` dropped the file's gravity.angle: the model's own scene had lost it,
    // until a recompile or `reload` read it back). A value the scene refuses is left to steer().
    std::optional<SceneDesc> scene;
    try {
      scene = scene_with(next);
    } catch (const SceneError&) {
    }
    const SceneDesc* as_set = scene ? &*scene : nullptr;
    std::string error;
    if (running()) {
      at_boundary([&] { error = steer(s.model_for_steering(), change, as_set); });
    } else {
      const Simulation::SteerOutcome outcome = s.steer_stopped(change, as_set);
      if (!outcome.refused.empty())
        throw std::runtime_error(typed + ": refused, the state cannot be solved under it (" + outcome.refused + ")");
      error = outcome.cannot;
    }
    if (error.empty()) {
      overrides_ = std::move(next);
      out_ << change.key << " = " << shown_word(change.value) << (running() ? " (from the next step)" : "") << "\n";
      note_step();
      preparation_note(s.state());
      if (const RenderSettings& r = s.model().render; change.key == "render.field" && !r.field_range_auto)
        out_ << "note: render.field_range = [" << format_number(r.field_range[0]) << ", "
             << format_number(r.field_range[1]) << "] colours it too (set render.field_range for " << r.field << ")\n";
      return;
    }
    // Not a change a running model can take (a shear mode switched on or off, ...): when stopped,
    // the scene is compiled again below.
    if (running()) throw std::runtime_error("set " + change.key + ": " + error);
  }
  if (running())
    throw std::runtime_error(several ? "set with several keys recompiles the scene: stop first"
                                     : "'" + change.key +
                                           "' cannot change while a run goes on (it is not steerable): stop first");
  // Recompile with the new values; keep the state of a run under way when the grains, the domain
  // and the fluid's grid are the same. Before the first step the state is made again from the
  // scene as changed (its positions, velocities, seed, a fluid's initial field), unless it was
  // given: a prepared packing (kPreparationKept) or a restored checkpoint (as `silt run --restore
  // X --set K=V`).
  // A refusal located at another key than the one typed (a value set before, the file's) says
  // which was typed: `set render.height 8193` answered "set render.width: ... 9000 x 8193", `set
  // fluid.reynolds 0.01` "set fluid.dt: ...".
  const auto compiled = [&] {
    try {
      return compile(scene_with(next));
    } catch (const SceneError& e) {
      if (!several && e.loc().file == "set " + change.key) throw;
      throw std::runtime_error(typed + ": refused with the value at " + e.loc().str() + ": " + e.message());
    }
  };
  Model m = compiled();
  // (grains frozen by `freeze` are kept frozen: the state was discarded as of other grains)
  const Simulation::Recompile how = s.after_recompile(m);
  const bool same = how == Simulation::Recompile::kStateKept;
  // (a wall moved through the settled grains was taken, and the next step failed on an overlap of
  // 2,062 %, advising stiffer contacts)
  if (same)
    if (const std::string conflict = s.kept_state_conflict(m); !conflict.empty())
      throw std::runtime_error(typed + ": refused, " + conflict);
  std::optional<State> keep;
  if (same) keep = s.state_to_carry();  // (the cycles go on from their phase: the state holds its origin)
  const State& was = s.state();
  const char* what = how == Simulation::Recompile::kGrainsChanged ? "the grains changed: back to t = 0"
                     : how == Simulation::Recompile::kGridChanged
                         ? "the domain or the fluid's grid changed: back to t = 0"
                         : "the state at t = 0 made again";
  std::string discarded = std::string(" (") + what;
  if (was.step > 0 || stats_->rows().size() > 1)
    discarded += "; discarded: the run to t = " + format_number(was.t) + s.model().unit("s") + " (step " +
                 std::to_string(was.step) + ") and its " + std::to_string(stats_->rows().size()) + " sample(s)";
  discarded += ")";
  install(std::move(m), keep);
  overrides_ = std::move(next);
  // (one line: what follows the values is of the change as a whole, not of its last key)
  for (size_t k = 0; k < changes.size(); ++k)
    out_ << (k ? ", " : "") << changes[k].key << " = " << shown_word(changes[k].value);
  out_ << (same ? " (state kept)" : discarded) << "\n";
  note_step();
  if (same) preparation_note(*keep);
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
  for (const Token& t : expand_lists(c.args)) names.push_back(t.text);
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
  for (size_t k = 0; k + 2 < n; ++k)
    for (const Token& t : expand_list(c.args[k])) w.names.push_back(t.text);
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
      v.draw.push_back(item);
    }
  }
  render::RenderScene rs;
  at_boundary([&] { rs = render::build_render_scene(s.model(), s.state(), v); });
  if (!raster_) raster_ = std::make_unique<render::Rasterizer>();
  render::Image img = raster_->draw(rs);
  render::compose_overlays(rs, img);
  check_not_open_file(c.args[0].text, "image");
  check_not_restored(c.args[0].text, "image");
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
  State st = read_checkpoint(file, s.model(), &differences);
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
