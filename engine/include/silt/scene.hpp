// The scene language: one schema, and SceneDesc, what a scene file said.
//
// Every key a scene may hold is declared once in the schema (engine/scene/schema.cpp) with its
// type, default, range, unit, whether it may change while a run goes on, and one line of doc.
// Reading a scene validates every value against it; SceneDesc keeps each value with its
// file:line:col so that compile() can point at the value it refuses. A value that was given but
// never read by compile() is an error too (it would otherwise be silently ignored).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "silt/errors.hpp"

namespace silt {

enum class KeyType { kBool, kInt, kReal, kString, kRealList, kRealMatrix, kBoolList, kStringList };
const char* key_type_name(KeyType t);

using Value = std::variant<bool, int64_t, double, std::string, std::vector<double>, std::vector<std::vector<double>>,
                           std::vector<bool>, std::vector<std::string>>;

// An inclusive or open interval for a number (or for every entry of a list of numbers).
struct Range {
  double lo = -1e308, hi = 1e308;
  bool lo_open = false, hi_open = false;
  bool contains(double x) const;
  std::string str() const;  // "[0, 1)", "> 0", ...
  static Range any() { return {}; }
  static Range positive() { return {0.0, 1e308, true, false}; }
  static Range non_negative() { return {0.0, 1e308, false, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
  static Range closed_open(double lo, double hi) { return {lo, hi, false, true}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
};

struct Model;

struct KeySpec {
  KeySpec() = default;
  KeySpec(std::string path_, KeyType type_, std::optional<Value> def_, Range range_, std::string unit_, bool steerable_,
          std::vector<std::string> choices_, std::string doc_)
      : path(std::move(path_)),
        type(type_),
        def(std::move(def_)),
        range(range_),
        unit(std::move(unit_)),
        steerable(steerable_),
        choices(std::move(choices_)),
        doc(std::move(doc_)) {}
  std::string path;  // dotted; an array of tables is written "grains[]"
  KeyType type = KeyType::kReal;
  std::optional<Value> def;  // no default: required, or one of several alternatives
  Range range;
  std::string unit;                  // "" for dimensionless
  bool steerable = false;            // may change between two steps of a running simulation
  std::vector<std::string> choices;  // allowed strings (kString, kStringList), empty = any
  std::string doc;
  // The value compile() chose when the scene gives none and there is no fixed default (a skin of
  // a tenth of the largest diameter, a time step from the contact time, ...), for `params`.
  std::function<std::string(const Model&)> computed;
  // The unit where the scene's form decides it (fluid.dt is in units of L / U when the scene gives
  // fluid.reynolds); empty: `unit`.
  std::function<std::string(const Model&)> unit_in;
  // Makes the state at t = 0 only (a seed, initial velocities, the first time step): a state kept
  // through a change of it goes on as it was, which the shell says.
  bool initial = false;
  std::string module;  // the module that owns the key (set when the schema is assembled)
};

// Constraints between keys, declared with the keys of a module and checked when a scene is read:
//   one_of: at most one of the alternatives may be given (each a set of keys: gravity.vector, or
//           gravity.magnitude with gravity.angle); a change of one replaces the others;
//   requires: `key` (given, or true for a boolean) needs one of `needs`.
struct KeyRule {
  enum class Kind { kOneOf, kRequires };
  Kind kind = Kind::kOneOf;
  std::vector<std::vector<std::string>> sides;  // kOneOf
  std::string key;                              // kRequires
  std::vector<std::string> needs;
  std::string why;  // the end of the message: "... needs box.pressure: <why>"
  static KeyRule one_of(std::vector<std::vector<std::string>> sides) {
    return {Kind::kOneOf, std::move(sides), {}, {}, {}};
  }
  static KeyRule requires_any(std::string key, std::vector<std::string> needs, std::string why) {
    return {Kind::kRequires, {}, std::move(key), std::move(needs), std::move(why)};
  }
};

// Every key of the modules silt knows (silt/module.hpp), module by module; a deque, so that
// pointers to keys stay valid when a module registers later.
const std::deque<KeySpec>& scene_schema();
const std::vector<KeyRule>& scene_rules();
// The keys `key` is an alternative to (KeyRule::one_of): fluid.reynolds for fluid.viscosity.
std::vector<std::string> alternatives_of(const std::string& key);
// The spec of a key path, with array indices normalised ("grains[3].radius" -> "grains[]...").
const KeySpec* find_key_spec(std::string_view path);
// Marks the keys of `paths` as making the state at t = 0 only (KeySpec::initial).
void mark_initial(std::vector<KeySpec>& keys, std::initializer_list<std::string_view> paths);
// A key's unit in a compiled model: its unit_in where it has one, none in reduced units.
std::string key_unit(const KeySpec& spec, const Model& m);
std::string normalise_key(std::string_view path);
// The closest known key to a misspelt one, or "" when nothing is close.
std::string suggest_key(std::string_view bad_path);
// Whether a normalised path names a list of tables ("grains") or a table ("contact").
bool is_group(std::string_view normalised);
bool is_table_prefix(std::string_view normalised);
// The error for a path that names no key: the nearest key, or the keys of the table it names.
std::string unknown_key_message(std::string_view path);
// A dotted key with its group indices bracketed, as scenes name them: "grains.0.count" ->
// "grains[0].count".
std::string canonical_key(const std::string& key);
std::string value_to_string(const Value& v);
// Why this model cannot draw `item` (of render.draw), or "": a field needs the fluid, lubrication
// forces the paste. For the scene's render.draw and the shell's `render FILE ITEMS` alike.
std::string draw_refusal(const Model& m, const std::string& item);

struct SceneEntry {
  Value value;
  FileLoc loc;
  const KeySpec* spec = nullptr;
};

class SceneDesc {
 public:
  std::string file;                           // the scene file ("" for a string scene)
  std::string text;                           // its full text, hashed into checkpoints
  std::map<std::string, SceneEntry> entries;  // concrete paths: "grains[0].radius"
  std::map<std::string, int> group_counts;    // "grains" -> number of [[grains]] tables
  std::map<std::string, FileLoc> tables;      // "domain", "grains[0]" -> where the table starts
  // The file's keys a --set replaced, each with the key set (an alternative to it, KeyRule::one_of).
  std::vector<std::pair<std::string, std::string>> replaced;

  bool has(std::string_view path) const;
  // The first of `paths` the scene gives, else `fallback`: where to report an error that more
  // than one key could have caused.
  std::string first_given(std::initializer_list<std::string_view> paths, std::string_view fallback) const;
  int group_count(std::string_view group) const;
  // For a canonical key of a group's entry ("grains[3].count"): why the scene has no such
  // entry (an index that is no whole number, or past the tables it has), "" when it has.
  std::string missing_entry(const std::string& path) const;
  // Whether the scene gives the table or a key in it ([fluid], or fluid.cells by --set).
  bool has_table(std::string_view table) const;
  // The value's location; for a key not given, where its table starts (the innermost one the
  // file has), else the start of the file: a missing key is reported where it belongs.
  FileLoc loc(std::string_view path) const;

  // Typed access to a value or its schema default; throws SceneError when absent and without
  // default. Marks the entry used.
  bool boolean(std::string_view path) const;
  int64_t integer(std::string_view path) const;
  double real(std::string_view path) const;
  std::string string(std::string_view path) const;
  std::vector<double> reals(std::string_view path) const;
  std::vector<std::vector<double>> matrix(std::string_view path) const;
  std::vector<bool> booleans(std::string_view path) const;
  std::vector<std::string> strings(std::string_view path) const;

  // A SceneError at the location of `path`.
  [[noreturn]] void fail(std::string_view path, const std::string& message) const;
  // Refuse a scene that breaks a KeyRule (two alternatives, a key without what it needs).
  void check_rules() const;
  // Remove the keys that `key` is an alternative to (a KeyRule::one_of).
  void erase_alternatives_of(const std::string& key);
  // Refuse values that were given but never read (pbrt's rule).
  void check_all_used() const;

 private:
  const Value* lookup(std::string_view path, KeyType want) const;
  mutable std::map<std::string, bool, std::less<>> used_;
};

// A `--set KEY=VALUE` override; VALUE is TOML (a bare word is taken as a string).
struct Override {
  std::string key;
  std::string value;
};
Override parse_override(const std::string& key_eq_value);  // throws SceneError
// Set one value of an already read scene, checked like the file's (throws SceneError).
void apply_override(SceneDesc& desc, const Override& o);

// Read and validate a scene. Throws SceneError ("file:line:col: message") on any bad input;
// throws IoError when the file cannot be read.
SceneDesc load_scene_file(const std::string& path, const std::vector<Override>& overrides = {});
SceneDesc parse_scene(const std::string& text, const std::string& name, const std::vector<Override>& overrides = {});

// The schema as a Markdown table (README) or aligned text (help).
std::string schema_markdown();
// The same, a line per key: `silt params`.
std::string schema_text();

}  // namespace silt
