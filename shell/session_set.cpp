// The shell's `set`: one or several KEY VALUE pairs as one change, steered into the running model
// where the key allows it, else compiled into a new one that keeps the state when it can.
#include <algorithm>
#include <optional>

#include "shell/session.hpp"
#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt::shell {
namespace {

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

// What a value taken does not change in this model, or "": the modules' (a paste's step and box
// are solved with its grains), and the shell's frames, which keep the cadence of `frames DIR every N`.
std::string inert_note(const Model& m, const std::string& key) {
  if (key == "render.every")
    return "render.every is silt run's frame cadence: the shell's frames keep theirs (`frames DIR every N`)";
  return inert_key_note(m, key);
}

}  // namespace

// One `set` as typed, and what the model was before it (for the notes after it).
struct Session::SetChange {
  std::vector<Override> changes;          // the pairs, keys canonical
  std::vector<std::pair<int, int>> cols;  // the columns of each pair's key and value
  std::string typed = "set";              // as typed, for messages
  std::vector<Override> next;             // the changes typed so far, with these last
  std::vector<std::string> replaced;      // the keys these are alternatives to
  // The keys of the alternatives these touch, on every side, and whether each was given before
  // (by the scene or an earlier set): those the change removes, and those it brings back.
  std::vector<std::pair<std::string, bool>> sides;
  bool was_fixed = false;  // the step before: fixed, and its value
  double dt_was = 0;
  std::vector<std::pair<std::string, std::string>> computed_was;

  bool typed_now(const std::string& key) const {
    return std::any_of(changes.begin(), changes.end(), [&](const Override& o) { return o.key == key; });
  }
  bool replaced_by(const std::string& key) const {
    return std::find(replaced.begin(), replaced.end(), key) != replaced.end();
  }
  bool several() const { return changes.size() > 1; }
  ParseError located(const SceneError& e) const;
};

// KEY VALUE, or several pairs taken as one change: values valid only together (a fluid's domain
// and its cells, whose spacing must be the same along every axis) could not be set one at a time.
Session::SetChange Session::read_set(const Command& c) {
  if (c.args.size() % 2 != 0)
    throw ParseError(c.args.back().col, "set takes KEY VALUE pairs: '" + c.args.back().text + "' has no value");
  SetChange ch;
  for (size_t k = 0; k < c.args.size(); k += 2) {
    const std::string key = canonical_key(c.args[k].text);
    const KeySpec* spec = find_key_spec(normalise_key(key));
    if (!spec) throw ParseError(c.args[k].col, unknown_key_message(key));
    // (an index with no entry, or with leading zeros, was located at the value)
    if (const std::string missing = sim().model().desc.missing_entry(key); !missing.empty())
      throw ParseError(c.args[k].col, missing);
    // A quoted word is the TOML string typed, escapes and all ("tab\there" kept its backslash,
    // where a scene file reads a tab), and a string for every key: `set output.every "5"` was 5,
    // where the scene file and --set refuse a string there.
    const Token& value = c.args[k + 1];
    ch.changes.push_back({key, !value.raw.empty() ? value.raw : value.text});
    ch.cols.push_back({c.args[k].col, value.col});
    // (a key and one it is an alternative to: the last had replaced the first, unsaid, where a
    // scene file giving both is refused)
    const std::vector<std::string> others = alternatives_of(key);
    for (size_t j = 0; j + 1 < ch.changes.size(); ++j) {
      if (ch.changes[j].key == key) throw ParseError(c.args[k].col, "set: '" + key + "' is given twice");
      if (std::find(others.begin(), others.end(), ch.changes[j].key) != others.end())
        throw ParseError(c.args[k].col,
                         "set: '" + ch.changes[j].key + "' and '" + key + "' are alternatives: give one of them");
    }
    ch.typed += " " + key + " " + shown_word(ch.changes.back().value);
  }
  // Each replaces an earlier value of its key, and the values of the keys it is an alternative to
  // (fluid.reynolds replaces fluid.viscosity).
  for (const Override& o : ch.changes) {
    const std::vector<std::string> others = alternatives_of(o.key);
    ch.replaced.insert(ch.replaced.end(), others.begin(), others.end());
    std::vector<std::string> all = others;  // (and the keys of o's own side: the others' alternatives)
    if (!others.empty()) {
      const std::vector<std::string> own = alternatives_of(others.front());
      all.insert(all.end(), own.begin(), own.end());
    }
    for (const std::string& k : all) {
      const bool listed = std::any_of(ch.sides.begin(), ch.sides.end(), [&](const auto& e) { return e.first == k; });
      if (!listed && !ch.typed_now(k)) ch.sides.push_back({k, sim().model().desc.has(k)});
    }
  }
  ch.next = overrides_;
  ch.next.erase(std::remove_if(ch.next.begin(), ch.next.end(),
                               [&](const Override& o) { return ch.typed_now(o.key) || ch.replaced_by(o.key); }),
                ch.next.end());
  ch.next.insert(ch.next.end(), ch.changes.begin(), ch.changes.end());
  const Model& m = sim().model();
  ch.was_fixed = !m.adaptive_dt;
  ch.dt_was = m.dt;
  ch.computed_was = computed_values(m);
  return ch;
}

// A scene error of a `set` as the shell reports it: at the value typed when it is one of this
// set's keys' (it was at the command), else naming what refused it.
ParseError Session::SetChange::located(const SceneError& e) const {
  for (size_t k = 0; k < changes.size(); ++k)
    if (e.loc().file == "set " + changes[k].key)
      return several() ? ParseError(cols[k].second, typed + ": " + e.message()) : ParseError(cols[k].second, e.what());
  // Another key's value refuses it: the file's (located there), or one set before in the shell
  // (its pseudo-file "set KEY" read as a location: "refused with the value at set fluid.dt").
  const std::string other = e.loc().file.starts_with("set ") ? "the value of an earlier `" + e.loc().file + "`"
                                                             : "the value at " + e.loc().str();
  return ParseError(cols.front().second, typed + ": refused with " + other + ": " + e.message());
}

// The model of the scene with this change. A refusal located at another key than the one typed
// (a value set before, the file's) says which was typed: `set render.height 8193` answered "set
// render.width: ... 9000 x 8193", `set fluid.reynolds 0.01` "set fluid.dt: ...".
Model Session::compile_set(const SetChange& ch) const {
  try {
    return compile(scene_with(ch.next));
  } catch (const SceneError& e) {
    throw ch.located(e);
  }
}

void Session::cmd_set(const Command& c) {
  const SetChange ch = read_set(c);
  const KeySpec* spec = find_key_spec(normalise_key(ch.changes.front().key));
  if (spec->steerable && !ch.several() && steer_set(ch)) return;
  if (running()) {
    // A change the scene refuses is said before "stop first" (a value out of its range, or an
    // unequal grid spacing that only compiling finds, was refused only once the run was stopped).
    // Compiling reads only the scene, not the running model.
    (void)compile_set(ch);
    throw ParseError(ch.cols.front().first,
                     ch.several() ? "set with several keys recompiles the scene: stop first"
                                  : "'" + ch.changes.front().key +
                                        "' cannot change while a run goes on (it is not steerable): stop first");
  }
  recompile_set(ch);
}

// A steerable key, into the model as it runs (or stands): false when the model cannot take it
// stopped (a shear mode switched on or off, ...), which a recompile then does.
bool Session::steer_set(const SetChange& ch) {
  Simulation& s = sim();
  const Override& change = ch.changes.front();
  // The scene as the file and the values typed make it: a key's alternatives come back from the
  // file when it replaces the value that had replaced them (`set gravity.vector V` then `set
  // gravity.magnitude G` dropped the file's gravity.angle: the model's own scene had lost it,
  // until a recompile or `reload` read it back). A value the scene refuses is left to steer().
  std::optional<SceneDesc> scene;
  try {
    scene = scene_with(ch.next);
  } catch (const SceneError&) {
  }
  const SceneDesc* as_set = scene ? &*scene : nullptr;
  std::string error;
  if (running()) {
    at_boundary([&] { error = steer(s.model_for_steering(), change, as_set); });
  } else {
    const Simulation::SteerOutcome outcome = s.steer_stopped(change, as_set);
    if (!outcome.refused.empty())
      throw std::runtime_error(ch.typed + ": refused, the state cannot be solved under it (" + outcome.refused + ")");
    error = outcome.cannot;
  }
  if (!error.empty()) {
    if (running()) throw ParseError(ch.cols.front().second, "set " + change.key + ": " + error);
    return false;
  }
  overrides_ = ch.next;
  out_ << change.key << " = " << shown_word(change.value) << (running() ? " (from the next step)" : "") << "\n";
  set_notes(ch, &s.state());
  if (const RenderSettings& r = s.model().render; change.key == "render.field" && !r.field_range_auto)
    out_ << "note: render.field_range = [" << format_number(r.field_range[0]) << ", " << format_number(r.field_range[1])
         << "] colours it too (set render.field_range for " << r.field << ")\n";
  return true;
}

// Recompile with the new values; keep the state of a run under way when the grains, the domain
// and the fluid's grid are the same. Before the first step the state is made again from the
// scene as changed (its positions, velocities, seed, a fluid's initial field), unless it was
// given: a prepared packing (kPreparationKept) or a restored checkpoint (as `silt run --restore
// X --set K=V`).
void Session::recompile_set(const SetChange& ch) {
  Simulation& s = sim();
  Model m = compile_set(ch);
  // (grains frozen by `freeze` are kept frozen: the state was discarded as of other grains)
  const Simulation::Recompile how = s.after_recompile(m);
  const bool same = how == Simulation::Recompile::kStateKept;
  // (a wall moved through the settled grains was taken, and the next step failed on an overlap of
  // 2,062 %, advising stiffer contacts)
  if (same)
    if (const std::string conflict = s.kept_state_conflict(m); !conflict.empty())
      throw std::runtime_error(ch.typed + ": refused, " + conflict);
  std::optional<State> keep;
  if (same) keep = s.state_to_carry();  // (the cycles go on from their phase: the state holds its origin)
  const State& was = s.state();
  const char* what = how == Simulation::Recompile::kGrainsChanged ? "the grains changed: back to t = 0"
                     : how == Simulation::Recompile::kGridChanged
                         ? "the domain or the fluid's grid changed: back to t = 0"
                         : "the state at t = 0 made again";
  std::string fate = same ? " (state kept)" : std::string(" (") + what;
  if (!same && (was.step > 0 || stats_->rows().size() > 1))
    fate += "; discarded: the run to t = " + format_number(was.t) + s.model().unit("s") + " (step " +
            std::to_string(was.step) + ") and its " + std::to_string(stats_->rows().size()) + " sample(s)";
  if (!same) fate += ")";
  // (a kept state the values could not solve was installed, said nothing, and made the next `run`
  // say "the last run failed", where the run had succeeded; refused as a steered value is)
  if (const std::string unsolved = install(std::move(m), keep); !unsolved.empty())
    throw std::runtime_error(ch.typed + ": refused, the state cannot be solved under it (" + unsolved + ")");
  overrides_ = ch.next;
  // (one line: what follows the values is of the change as a whole, not of its last key)
  for (size_t k = 0; k < ch.changes.size(); ++k)
    out_ << (k ? ", " : "") << ch.changes[k].key << " = " << shown_word(ch.changes[k].value);
  out_ << fate << "\n";
  set_notes(ch, same ? &*keep : nullptr);
}

// What changed with the values set besides them: a value compile() computes from them, a fixed step
// that another key changed (fluid.reynolds over a scene's fluid.viscosity makes its fluid.dt read
// in units of L / U, and a channel's step doubled without a word), a packing kept from before.
void Session::set_notes(const SetChange& ch, const State* kept) {
  const Model& m = sim().model();  // (a recompile installs another simulation)
  for (const Override& o : ch.changes)
    if (const std::string inert = inert_note(m, o.key); !inert.empty()) out_ << "note: " << inert << "\n";
  // (`set lubrication.dt` removed a scene's lubrication.dt_max and drift_max without a word)
  // (and a set of the first side again brought back the scene's values of it without a word)
  std::vector<std::string> dropped, back;
  for (const auto& [key, before] : ch.sides) {
    if (before && !m.desc.has(key)) dropped.push_back(key);
    if (!before && m.desc.has(key)) back.push_back(key);
  }
  const auto list = [this](const std::vector<std::string>& keys) {
    for (size_t k = 0; k < keys.size(); ++k) out_ << (k ? ", " : " ") << keys[k];
  };
  if (!dropped.empty()) {
    out_ << "note: " << (ch.several() ? std::string("these values replace") : ch.changes[0].key + " replaces");
    list(dropped);
    out_ << ", " << (dropped.size() == 1 ? "an alternative" : "alternatives") << " given before\n";
  }
  if (!back.empty()) {
    out_ << "note: the scene's";
    list(back);
    out_ << (back.size() == 1 ? " applies" : " apply") << " again (the alternative that had replaced "
         << (back.size() == 1 ? "it" : "them") << " is gone)\n";
  }
  // (a lid's speed set in a scene given by fluid.reynolds changed the viscosity, and the shell
  // said only the speed)
  for (const auto& now : computed_values(m)) {
    const std::string& key = now.first;
    const std::string& value = now.second;
    const auto was =
        std::find_if(ch.computed_was.begin(), ch.computed_was.end(), [&](const auto& kv) { return kv.first == key; });
    if (was == ch.computed_was.end() || was->second == value || ch.typed_now(key) || ch.replaced_by(key)) continue;
    const std::string unit = key_unit(*find_key_spec(key), m);
    out_ << "note: " << key << " is now " << value << (unit.empty() ? "" : " " + unit) << " (it was " << was->second
         << "), computed from the scene as it now reads\n";
  }
  // (not for the key that sets the step, nor its alternative: run.dt_over_tc is run.dt's)
  const std::vector<std::string> sets_step = alternatives_of(m.dt_key);
  const bool step_typed = ch.typed_now(m.dt_key) || std::any_of(sets_step.begin(), sets_step.end(),
                                                                [&](const std::string& k) { return ch.typed_now(k); });
  if (ch.was_fixed && !m.adaptive_dt && m.dt != ch.dt_was && !step_typed)
    out_ << "note: the time step is now " << format_number(m.dt) << m.unit("s") << " (it was "
         << format_number(ch.dt_was) << m.unit("s") << "), "
         << (m.dt_key == "run.dt" && !m.desc.has("run.dt")
                 ? std::string("the default step (0.02 t_c) of the scene as it now reads")
                 : "from " + m.dt_key + " as the scene now reads it")
         << "\n";
  if (kept && kept->step == 0 && m.prepare.compress &&
      std::any_of(ch.changes.begin(), ch.changes.end(), [](const Override& o) { return enters_preparation(o.key); }))
    out_ << kPreparationKept;
  // (a first step, a seed or an initial field set past the start was taken, "(state kept)", and did
  // nothing)
  if (kept && kept->step > 0)
    for (const Override& o : ch.changes)
      if (const KeySpec* spec = find_key_spec(normalise_key(o.key)); spec && spec->initial)
        out_ << "note: " << o.key << " makes the state at t = 0 only: the state kept (step " << kept->step
             << ") goes on as it was; `reset` starts again with it\n";
}

}  // namespace silt::shell
