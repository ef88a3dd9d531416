// SceneDesc: typed access to what the scene said, with the schema's defaults, and the
// "every given value was read" rule.
#include <algorithm>
#include <sstream>

#include "core/assert.hpp"
#include "silt/model.hpp"
#include "silt/scene.hpp"
#include "silt/text.hpp"

namespace silt {

std::string normalise_key(std::string_view path) {
  std::string out;
  out.reserve(path.size());
  for (size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '[') {
      out += "[]";
      while (i < path.size() && path[i] != ']') ++i;
    } else {
      out += path[i];
    }
  }
  return out;
}

const KeySpec* find_key_spec(std::string_view path) {
  const std::string norm = normalise_key(path);
  for (const KeySpec& k : scene_schema())
    if (k.path == norm) return &k;
  return nullptr;
}

std::string key_unit(const KeySpec& spec, const Model& m) {
  return m.unit_name(spec.unit_in ? spec.unit_in(m) : spec.unit);
}

std::string suggest_key(std::string_view bad_path) {
  const std::string norm = normalise_key(bad_path);
  const auto dot = norm.rfind('.');
  const std::string leaf = dot == std::string::npos ? norm : norm.substr(dot + 1);
  std::string best;
  // Edits are counted against the last name, the one mistyped: a path's length would let "contact.nope"
  // suggest "contact.model".
  size_t best_d = std::max<size_t>(2, leaf.size() / 3) + 1;
  for (const KeySpec& k : scene_schema()) {
    // Compare whole paths, and leaves alone so that a key in the wrong table is found too.
    const auto kdot = k.path.rfind('.');
    const std::string kleaf = kdot == std::string::npos ? k.path : k.path.substr(kdot + 1);
    // A leaf alone is short: two edits turn "nope" into "name". Take it only within a third of its length,
    // and not below 4 letters in another table ("lubrication.foo" is not "render.camera.fov").
    const size_t leaf_d = edit_distance(leaf, kleaf, best_d);
    const bool leaf_counts = leaf_d <= std::max<size_t>(1, leaf.size() / 3) && (norm == leaf || leaf.size() >= 4);
    const size_t d =
        std::min(edit_distance(norm, k.path, best_d), leaf_counts ? leaf_d + (norm == leaf ? 0 : 1) : SIZE_MAX);
    if (d < best_d) {
      best_d = d;
      best = k.path;
    }
    // The tables that hold the key, for a misspelt table name: "[contakt]" -> "contact".
    for (auto p = k.path.find('.'); p != std::string::npos; p = k.path.find('.', p + 1))
      if (const size_t dt = edit_distance(norm, k.path.substr(0, p), best_d); dt < best_d) {
        best_d = dt;
        best = k.path.substr(0, p);
      }
  }
  // Report with the user's indices: "grains[2].raduis" -> "grains[2].radius".
  if (const auto lb = bad_path.find('['); lb != std::string_view::npos && best.find("[]") != std::string::npos) {
    const auto rb = bad_path.find(']', lb);
    best.replace(best.find("[]"), 2, std::string(bad_path.substr(lb, rb - lb + 1)));
  }
  // A path written without an index gets the first entry's ("grains.count" was told
  // "grains[].count", itself refused).
  for (auto b = best.find("[]"); b != std::string::npos; b = best.find("[]", b)) best.replace(b, 2, "[0]");
  return best;
}

namespace {
bool any_key_under(std::string_view normalised, std::string_view suffix) {
  const std::string prefix = std::string(normalised) + std::string(suffix);
  for (const KeySpec& k : scene_schema())
    if (k.path.rfind(prefix, 0) == 0) return true;
  return false;
}
}  // namespace

bool is_group(std::string_view normalised) { return any_key_under(normalised, "[]"); }

bool is_table_prefix(std::string_view normalised) { return any_key_under(normalised, "."); }

std::string unknown_key_message(std::string_view path) {
  const std::string norm = normalise_key(path);
  const bool group = is_group(norm);
  if (group || is_table_prefix(norm)) {
    // A table named where a key is wanted ("set gravity ...", "gravity = 1"): list its keys, not
    // a near name, which would be the table itself.
    const std::string prefix = norm + (group ? "[]." : ".");
    std::string keys;
    int listed = 0, more = 0;
    for (const KeySpec& k : scene_schema()) {
      if (k.path.rfind(prefix, 0) != 0) continue;
      if (listed == 6) {
        ++more;
        continue;
      }
      std::string key = k.path;
      for (auto b = key.find("[]"); b != std::string::npos; b = key.find("[]", b)) key.replace(b, 2, "[K]");
      keys += (listed++ ? ", " : "") + key;
    }
    if (more) keys += " and " + std::to_string(more) + " more";
    return "'" + std::string(path) + "' is " + (group ? "a list of tables" : "a table") + ", not a key: its keys are " +
           keys;
  }
  std::string msg = "unknown key '" + std::string(path) + "'";
  if (const std::string hint = suggest_key(path); !hint.empty()) msg += "; did you mean '" + hint + "'?";
  return msg;
}

std::string value_to_string(const Value& v) {
  std::ostringstream o;
  o.precision(10);
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>) o << (x ? "true" : "false");
        else if constexpr (std::is_same_v<T, int64_t> || std::is_same_v<T, double>) o << x;
        else if constexpr (std::is_same_v<T, std::string>) o << toml_quoted(x);
        else if constexpr (std::is_same_v<T, std::vector<std::vector<double>>>) {
          o << "[";
          for (size_t i = 0; i < x.size(); ++i) {
            o << (i ? ", [" : "[");
            for (size_t j = 0; j < x[i].size(); ++j) o << (j ? ", " : "") << x[i][j];
            o << "]";
          }
          o << "]";
        } else {
          o << "[";
          for (size_t i = 0; i < x.size(); ++i) {
            o << (i ? ", " : "");
            if constexpr (std::is_same_v<T, std::vector<std::string>>) o << toml_quoted(x[i]);
            else if constexpr (std::is_same_v<T, std::vector<bool>>) o << (x[i] ? "true" : "false");
            else o << x[i];
          }
          o << "]";
        }
      },
      v);
  return o.str();
}

bool SceneDesc::has(std::string_view path) const { return entries.count(std::string(path)) > 0; }

std::string SceneDesc::first_given(std::initializer_list<std::string_view> paths, std::string_view fallback) const {
  for (std::string_view p : paths)
    if (has(p)) return std::string(p);
  return std::string(fallback);
}

bool SceneDesc::has_table(std::string_view table) const {
  if (tables.count(std::string(table))) return true;
  const std::string prefix = std::string(table) + ".";
  const auto it = entries.lower_bound(prefix);
  return it != entries.end() && it->first.compare(0, prefix.size(), prefix) == 0;
}

int SceneDesc::group_count(std::string_view group) const {
  auto it = group_counts.find(std::string(group));
  return it == group_counts.end() ? 0 : it->second;
}

FileLoc SceneDesc::loc(std::string_view path) const {
  auto it = entries.find(std::string(path));
  if (it != entries.end()) return it->second.loc;
  std::string table(path);
  for (auto dot = table.rfind('.'); dot != std::string::npos; dot = table.rfind('.')) {
    table.resize(dot);
    if (auto t = tables.find(table); t != tables.end()) return t->second;
  }
  return FileLoc{file, 1, 1};
}

void SceneDesc::fail(std::string_view path, const std::string& message) const { throw SceneError(loc(path), message); }

const Value* SceneDesc::lookup(std::string_view path, KeyType want) const {
  const KeySpec* spec = find_key_spec(path);
  if (!spec || spec->type != want)
    throw std::logic_error("scene key '" + std::string(path) + "' read with the wrong type");
  auto it = entries.find(std::string(path));
  if (it != entries.end()) {
    used_[std::string(path)] = true;
    return &it->second.value;
  }
  if (spec->def) return &*spec->def;
  // (with what may stand for it: a fluid without its viscosity was not told of fluid.reynolds)
  std::string instead;
  for (const std::string& other : alternatives_of(normalise_key(path)))
    instead += (instead.empty() ? " (or " : ", or ") + std::string("'") + other + "'";
  throw SceneError(loc(path),
                   "missing required key '" + std::string(path) + "'" + (instead.empty() ? "" : instead + ")"));
}

bool SceneDesc::boolean(std::string_view p) const { return std::get<bool>(*lookup(p, KeyType::kBool)); }
int64_t SceneDesc::integer(std::string_view p) const { return std::get<int64_t>(*lookup(p, KeyType::kInt)); }
double SceneDesc::real(std::string_view p) const { return std::get<double>(*lookup(p, KeyType::kReal)); }
std::string SceneDesc::string(std::string_view p) const { return std::get<std::string>(*lookup(p, KeyType::kString)); }
std::vector<double> SceneDesc::reals(std::string_view p) const {
  return std::get<std::vector<double>>(*lookup(p, KeyType::kRealList));
}
std::vector<std::vector<double>> SceneDesc::matrix(std::string_view p) const {
  return std::get<std::vector<std::vector<double>>>(*lookup(p, KeyType::kRealMatrix));
}
std::vector<bool> SceneDesc::booleans(std::string_view p) const {
  return std::get<std::vector<bool>>(*lookup(p, KeyType::kBoolList));
}
std::vector<std::string> SceneDesc::strings(std::string_view p) const {
  return std::get<std::vector<std::string>>(*lookup(p, KeyType::kStringList));
}

namespace {

std::string list_keys(const std::vector<std::string>& keys, const char* sep) {
  std::string out;
  for (size_t k = 0; k < keys.size(); ++k)
    out += (k ? (k + 1 == keys.size() ? std::string(" ") + sep + " " : ", ") : "") + keys[k];
  return out;
}

// "run.dt", "gravity.magnitude (with gravity.angle)".
std::string side_text(const std::vector<std::string>& side) {
  std::string out = side[0];
  if (side.size() > 1) out += " (with " + list_keys({side.begin() + 1, side.end()}, "and") + ")";
  return out;
}

}  // namespace

void SceneDesc::check_rules() const {
  for (const KeyRule& r : scene_rules()) {
    if (r.kind == KeyRule::Kind::kOneOf) {
      const std::vector<std::string>* first = nullptr;
      for (const auto& side : r.sides) {
        const std::string* given = nullptr;
        for (const std::string& k : side)
          if (has(k)) {
            given = &k;
            break;
          }
        if (!given) continue;
        if (!first) {
          first = &side;
          continue;
        }
        std::vector<std::string> names;
        for (const auto& s : r.sides) names.push_back(side_text(s));
        fail(*given, r.sides.size() == 2 ? "give " + names[0] + " or " + names[1] + ", not both"
                                         : "give one of " + list_keys(names, "and") + ", not two");
      }
      continue;
    }
    if (!has(r.key)) continue;
    const auto& e = entries.at(r.key);
    if (const bool* b = std::get_if<bool>(&e.value); b && !*b) continue;  // a boolean needs only when true
    bool met = false;
    for (const std::string& k : r.needs) met = met || has(k);
    if (!met) fail(r.key, r.key + " needs " + list_keys(r.needs, "or") + ": " + r.why);
  }
}

void SceneDesc::erase_alternatives_of(const std::string& key) {
  for (const std::string& k : alternatives_of(key)) entries.erase(k);
}

void mark_initial(std::vector<KeySpec>& keys, std::initializer_list<std::string_view> paths) {
  for (std::string_view path : paths) {
    const auto it = std::find_if(keys.begin(), keys.end(), [&](const KeySpec& k) { return k.path == path; });
    SILT_ASSERT(it != keys.end(), "mark_initial: no key " + std::string(path));
    it->initial = true;
  }
}

std::vector<std::string> alternatives_of(const std::string& key) {
  std::vector<std::string> out;
  for (const KeyRule& r : scene_rules()) {
    if (r.kind != KeyRule::Kind::kOneOf) continue;
    for (const auto& side : r.sides) {
      if (std::find(side.begin(), side.end(), key) == side.end()) continue;
      for (const auto& other : r.sides)
        if (&other != &side) out.insert(out.end(), other.begin(), other.end());
    }
  }
  return out;
}

void SceneDesc::check_all_used() const {
  for (const auto& [path, entry] : entries) {
    if (used_.count(path)) continue;
    throw SceneError(entry.loc, "'" + path + "' is set but not used by this scene " +
                                    "(it does not apply to the chosen model or placement)");
  }
}

}  // namespace silt
