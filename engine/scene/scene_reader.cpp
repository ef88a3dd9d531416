// TOML text -> SceneDesc: every value checked against the schema and kept with its location.
#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "silt/input_files.hpp"
#include "silt/scene.hpp"
#include "silt/text.hpp"

namespace silt {
namespace {

FileLoc loc_of(const toml::source_region& r, const std::string& file) {
  return FileLoc{file, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
}

// A number written past the doubles' range (1e309, -2e308): TOML reads no value from it.
bool beyond_doubles(const std::string& token) {
  if (token.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && errno == ERANGE && std::isinf(x);
}
const char* const kBeyond = " is beyond 1e308, the largest magnitude a scene takes";

// A number written below the doubles' range (1e-400): TOML reads it as 0, which turns some keys
// off (lubrication.stress_tolerance), so it is refused where it is written.
const char* const kBelow = " is below 4.9e-324 in magnitude, the smallest a number takes (it would read as 0)";

// The literals nodes were read from: a number's characters at its line and column (in characters,
// as the parser counts) of `text`; the lines' starts found once.
class Literals {
 public:
  explicit Literals(std::string_view text) : text_(text) {}
  std::string_view at(const toml::source_position& p) {
    if (starts_.empty()) {
      starts_.push_back(0);
      for (size_t k = 0; k < text_.size(); ++k)
        if (text_[k] == '\n') starts_.push_back(k + 1);
    }
    if (p.line < 1 || p.line > starts_.size()) return {};
    // From the last literal when this one is further on its line (an array's items come in order:
    // a list of 90,000 positions on one line took 32 s walked from the line's start each time).
    const bool on = p.line == line_ && p.column >= column_;
    size_t pos = on ? pos_ : starts_[p.line - 1];
    for (uint32_t col = on ? column_ : 1; col < p.column && pos < text_.size(); ++col) {
      ++pos;
      while (pos < text_.size() && (static_cast<unsigned char>(text_[pos]) & 0xC0) == 0x80) ++pos;
    }
    line_ = p.line;
    column_ = p.column;
    pos_ = pos;
    size_t end = pos;
    while (end < text_.size() && std::string_view("0123456789.eE+-_").find(text_[end]) != std::string_view::npos) ++end;
    return pos < text_.size() ? text_.substr(pos, end - pos) : std::string_view();
  }

 private:
  std::string_view text_;
  std::vector<size_t> starts_;
  uint32_t line_ = 0, column_ = 0;  // the last literal's, at byte pos_
  size_t pos_ = 0;
};

// Every floating-point value of `n` that reads 0 from a literal that is not 0, refused at
// loc(its node).
template <class Loc>
void refuse_underflow(const toml::node& n, Literals& text, const Loc& loc) {
  if (const auto* t = n.as_table()) {
    for (const auto& entry : *t) refuse_underflow(entry.second, text, loc);
  } else if (const auto* a = n.as_array()) {
    for (const toml::node& v : *a) refuse_underflow(v, text, loc);
  } else if (n.is_floating_point() && *n.value<double>() == 0.0) {
    const std::string_view lit = text.at(n.source().begin);
    const std::string_view mantissa = lit.substr(0, lit.find_first_of("eE"));
    if (mantissa.find_first_of("123456789") != std::string_view::npos)
      throw SceneError(loc(n), std::string(lit) + kBelow);
  }
}

// A list of strings typed with bare words as items ([field, colorbar], as the shell's `print` and
// `render` lists take them, and as a bare word is a string on its own) with those items quoted:
// ["field", "colorbar"]. Quoted items are kept as typed; nothing when an item is neither (a
// bracket, a brace, a '#' or an '=' in it, or an empty one but a trailing comma's).
std::optional<std::string> quote_bare_items(const std::string& text) {
  const size_t open = text.find_first_not_of(" \t"), close = text.find_last_not_of(" \t");
  if (open == std::string::npos || text[open] != '[' || text[close] != ']') return std::nullopt;
  std::vector<std::string> items(1);
  char quote = 0;
  for (size_t i = open + 1; i < close; ++i) {
    const char c = text[i];
    if (quote) quote = c == quote && (quote == '\'' || text[i - 1] != '\\') ? 0 : quote;
    else if (c == '"' || c == '\'') quote = c;
    else if (c == ',') {
      items.emplace_back();
      continue;
    }
    items.back() += c;
  }
  if (quote) return std::nullopt;
  std::string out = "[";
  for (size_t k = 0; k < items.size(); ++k) {
    const size_t b = items[k].find_first_not_of(" \t"), e = items[k].find_last_not_of(" \t");
    if (b == std::string::npos) {
      if (k + 1 == items.size() && k > 0) break;  // a trailing comma
      return std::nullopt;
    }
    const std::string item = items[k].substr(b, e - b + 1);
    const bool quoted = item[0] == '"' || item[0] == '\'';
    if (!quoted && item.find_first_of("[]{}#=\"'") != std::string::npos) return std::nullopt;
    out += (k ? ", " : "") + (quoted ? item : toml_quoted(item));
  }
  return out + "]";
}

// The parser's error, or for a number past the doubles' range what it is, at its first character
// (the parser's report read "could not be interpreted as a value", one column past its end).
SceneError parse_error(const toml::parse_error& e, const std::string& file) {
  const std::string what(e.description());
  FileLoc at = loc_of(e.source(), file);
  const size_t open = what.find('\''), close = open == std::string::npos ? open : what.find('\'', open + 1);
  if (close != std::string::npos) {
    const std::string token = what.substr(open + 1, close - open - 1);
    if (beyond_doubles(token)) {
      at.col = std::max(1, at.col - static_cast<int>(token.size()));
      return SceneError(at, token + kBeyond);
    }
  }
  return SceneError(at, what);
}

std::optional<double> as_number(const toml::node& n) {
  if (n.is_integer()) return static_cast<double>(*n.value<int64_t>());
  if (n.is_floating_point()) return *n.value<double>();
  return std::nullopt;
}

// Convert a TOML node to the schema's type; returns an error message or "".
std::string convert(const toml::node& n, const KeySpec& spec, const std::string& path, Value& out, FileLoc& where,
                    const std::string& file) {
  auto type_error = [&] {
    const std::string type = key_type_name(spec.type);
    return "'" + path + "' must be " + (type[0] == 'i' ? "an " : "a ") + type;
  };
  // (shown: an integer as given, which its double rounds past 2^53: 9223372036854775807 read
  // ...808)
  auto check_range = [&](double x, const toml::node& at, std::string_view shown = {}) -> std::string {
    if (spec.range.contains(x)) return "";
    where = loc_of(at.source(), file);
    std::ostringstream o;
    // nan and inf are TOML numbers, and no quantity of a scene.
    if (!std::isfinite(x)) return "'" + path + "' = " + (std::isnan(x) ? "nan" : "inf") + " is not a finite number";
    // The value in full (its shortest exact form): 10000001 printed to six digits reads 1e+07,
    // as if it were the bound it exceeds.
    char full[32];
    const auto [end, ec] = std::to_chars(full, full + sizeof full, x);
    o << "'" << path << "' = " << (shown.empty() ? std::string_view(full, ec == std::errc() ? end - full : 0) : shown);
    // A scene's numbers stop at 1e308 in magnitude, whatever the key's own range.
    if (std::abs(x) > 1e308) o << kBeyond;
    else o << " is out of range " << spec.range.str() << (spec.unit.empty() ? "" : " " + spec.unit);
    return o.str();
  };
  auto as_given = [](const toml::node& e) {
    return e.is_integer() ? std::to_string(*e.value<int64_t>()) : std::string();
  };
  auto check_choice = [&](const std::string& s, const toml::node& at) -> std::string {
    if (spec.choices.empty()) return "";
    for (const auto& c : spec.choices)
      if (c == s) return "";
    where = loc_of(at.source(), file);
    std::string msg = "'" + path + "' = \"" + s + "\" is not one of:";
    for (const auto& c : spec.choices) msg += " " + c;
    return msg;
  };
  switch (spec.type) {
    case KeyType::kBool:
      if (!n.is_boolean()) return type_error();
      out = *n.value<bool>();
      return "";
    case KeyType::kInt: {
      auto x = as_number(n);
      // Whole and within int64 before it is converted (nan, inf and 1e300 are not integers).
      if (!x || !std::isfinite(*x) || *x != std::floor(*x)) return type_error();
      // (an integer past the key's range and int64's, 2^63 - 1 points, is out of that range: it
      // read "must be an integer")
      const std::string shown = as_given(n);
      if (!(std::abs(*x) < 9.2e18)) {
        const std::string range = check_range(*x, n, shown);
        return range.empty() ? type_error() : range;
      }
      out = static_cast<int64_t>(*x);
      return check_range(*x, n, shown);
    }
    case KeyType::kReal: {
      auto x = as_number(n);
      if (!x) return type_error();
      out = *x;
      return check_range(*x, n);
    }
    case KeyType::kString:
      if (!n.is_string()) return type_error();
      out = std::string(*n.value<std::string_view>());
      return check_choice(std::get<std::string>(out), n);
    case KeyType::kRealList: {
      if (!n.is_array()) return type_error();
      std::vector<double> v;
      for (const toml::node& e : *n.as_array()) {
        auto x = as_number(e);
        if (!x) return type_error();
        if (auto err = check_range(*x, e, as_given(e)); !err.empty()) return err;
        v.push_back(*x);
      }
      out = std::move(v);
      return "";
    }
    case KeyType::kRealMatrix: {
      if (!n.is_array()) return type_error();
      std::vector<std::vector<double>> m;
      for (const toml::node& row : *n.as_array()) {
        if (!row.is_array()) return type_error();
        std::vector<double> v;
        for (const toml::node& e : *row.as_array()) {
          auto x = as_number(e);
          if (!x) return type_error();
          if (auto err = check_range(*x, e, as_given(e)); !err.empty()) return err;
          v.push_back(*x);
        }
        m.push_back(std::move(v));
      }
      out = std::move(m);
      return "";
    }
    case KeyType::kBoolList: {
      if (!n.is_array()) return type_error();
      std::vector<bool> v;
      for (const toml::node& e : *n.as_array()) {
        if (!e.is_boolean()) return type_error();
        v.push_back(*e.value<bool>());
      }
      out = std::move(v);
      return "";
    }
    case KeyType::kStringList: {
      if (!n.is_array()) return type_error();
      std::vector<std::string> v;
      for (const toml::node& e : *n.as_array()) {
        if (!e.is_string()) return type_error();
        v.emplace_back(*e.value<std::string_view>());
        if (auto err = check_choice(v.back(), e); !err.empty()) return err;
      }
      out = std::move(v);
      return "";
    }
  }
  return type_error();
}

class Reader {
 public:
  Reader(SceneDesc& desc, std::string file) : desc_(desc), file_(std::move(file)) {}

  void table(const toml::table& t, const std::string& prefix) {
    for (auto&& [key, node] : t) {
      const std::string name(key.str());
      const std::string path = prefix.empty() ? name : prefix + "." + name;
      const FileLoc where = loc_of(key.source(), file_);
      const std::string norm = normalise_key(path);
      if (node.is_table()) {
        if (is_group(norm)) throw SceneError(where, "'" + path + "' is a list of tables: write [[" + path + "]]");
        // A key given a table (`friction.x = 0.25`, `friction = {a = 1}`): its type, not "unknown
        // key 'contact.friction'; did you mean 'contact.friction'?"
        if (const KeySpec* spec = find_key_spec(norm))
          throw SceneError(where, "'" + path + "' takes a value (" + key_type_name(spec->type) + "), not a table");
        if (!is_table_prefix(norm)) throw SceneError(where, unknown_key_message(path));
        desc_.tables[path] = loc_of(node.source(), file_);
        table(*node.as_table(), path);
      } else if (node.is_array_of_tables() && is_group(norm)) {
        int index = 0;
        for (const toml::node& e : *node.as_array()) {
          const std::string element = path + "[" + std::to_string(index++) + "]";
          desc_.tables[element] = loc_of(e.source(), file_);
          table(*e.as_table(), element);
        }
        desc_.group_counts[path] = index;
      } else {
        leaf(path, norm, node, where);
      }
    }
  }

  void leaf(const std::string& path, const std::string& norm, const toml::node& node, const FileLoc& key_loc) {
    const KeySpec* spec = find_key_spec(norm);
    if (!spec) throw SceneError(key_loc, unknown_key_message(path));
    SceneEntry e;
    e.spec = spec;
    e.loc = loc_of(node.source(), file_);
    FileLoc where = e.loc;
    const std::string err = convert(node, *spec, path, e.value, where, file_);
    if (!err.empty()) throw SceneError(where, err);
    desc_.entries[path] = std::move(e);
  }

 private:
  SceneDesc& desc_;
  std::string file_;
};

// `batch`: one of the command line's --set list, which may not hold two alternatives.
void apply_override_at(SceneDesc& desc, const Override& o, int ordinal, bool batch) {
  const FileLoc where{"--set", ordinal, static_cast<int>(o.key.size()) + 2};
  // (a control byte went into a scene's name, and was echoed raw in an unknown key's message)
  const std::string typed = o.key + "=" + o.value;
  for (size_t i = 0; i < typed.size(); ++i)
    if (is_control(typed[i]) && typed[i] != '\t' && typed[i] != '\n' && typed[i] != '\r')  // (TOML's blanks)
      throw SceneError(FileLoc{"--set", ordinal, static_cast<int>(i) + 1}, "control character");
  const std::string path = canonical_key(o.key);
  const std::string norm = normalise_key(path);
  const KeySpec* spec = find_key_spec(norm);
  // (the key's errors at the key, column 1; the value's after "KEY=")
  const FileLoc at_key{"--set", ordinal, 1};
  if (!spec) throw SceneError(at_key, unknown_key_message(path));
  if (const std::string missing = desc.missing_entry(path); !missing.empty()) throw SceneError(at_key, missing);
  toml::table t;
  if (beyond_doubles(o.value)) throw SceneError(where, "'" + path + "' = " + o.value + kBeyond);
  const auto parse = [](const std::string& text) {
    return toml::parse(std::string_view("v = " + text), std::string_view("--set"));
  };
  // A value that begins as a TOML string, list or table is read as one, or refused ("unterminated
  // was kept with its quote).
  const bool toml_form = !o.value.empty() && std::string_view("\"'[{").find(o.value[0]) != std::string_view::npos;
  try {
    t = parse(o.value);
  } catch (const toml::parse_error& e) {
    // (render.draw=[field] was "Error while parsing boolean: expected 'false', saw 'fi'")
    const auto quoted = spec->type == KeyType::kStringList ? quote_bare_items(o.value) : std::nullopt;
    try {
      if (quoted) t = parse(*quoted);
    } catch (const toml::parse_error&) {
    }
    if (toml_form && !t.get("v"))
      throw SceneError(where, "cannot read the value of " + o.key + ": " + std::string(e.description()));
  }
  // A bare word is a string, as typed (its quotes and backslashes were read as escapes); so is a
  // word that reads as a number, a boolean or a date, for a key that takes a string
  // (grains.0.name=5 was refused as not a string).
  const toml::node* v = t.get("v");
  if (v) {
    const std::string as_toml = "v = " + o.value;
    Literals literals(as_toml);
    refuse_underflow(*v, literals, [&](const toml::node&) { return where; });
  }
  // (a whole number past int64's reach, which TOML cannot read, was "must be an integer")
  const std::string_view digits = std::string_view(o.value).substr(o.value[0] == '-' || o.value[0] == '+' ? 1 : 0);
  if (!v && spec->type == KeyType::kInt && digits.size() >= 19 && digits[0] != '0' &&
      digits.find_first_not_of("0123456789") == std::string_view::npos)
    throw SceneError(where, "'" + path + "' = " + o.value + " is out of range " + spec->range.str() +
                                (spec->unit.empty() ? "" : " " + spec->unit) +
                                " (and beyond the integers', 9223372036854775807 in magnitude)");
  if (!v || (spec->type == KeyType::kString && !toml_form && !v->is_string())) {
    try {
      t = parse(toml_quoted(o.value));
    } catch (const toml::parse_error& e) {
      throw SceneError(where, "cannot read the value of " + o.key + ": " + std::string(e.description()));
    }
  }
  SceneEntry e;
  e.spec = spec;
  e.loc = where;
  FileLoc err_loc = where;
  const std::string err = convert(*t.get("v"), *spec, path, e.value, err_loc, "--set");
  if (!err.empty()) throw SceneError(where, err);
  // As the shell's `set`: a key replaces the keys of the file it is an alternative to (run.dt
  // run.dt_over_tc), which the command line says; two of them on the command line would leave the
  // last alone, unsaid.
  for (const std::string& other : batch ? alternatives_of(path) : std::vector<std::string>{}) {
    const auto it = desc.entries.find(other);
    if (it == desc.entries.end()) continue;
    if (it->second.loc.file == "--set")
      throw SceneError(where, "'" + path + "' and '" + other + "' (--set " + std::to_string(it->second.loc.line) +
                                  ") are alternatives: give one of them");
    desc.replaced.emplace_back(other, path);
  }
  desc.entries[path] = std::move(e);
  desc.erase_alternatives_of(path);
}

}  // namespace

std::string canonical_key(const std::string& key) {
  std::string out;
  std::string part;
  std::istringstream in(key);
  while (std::getline(in, part, '.')) {
    const bool index = !part.empty() && part.find_first_not_of("0123456789") == std::string::npos;
    if (index && !out.empty()) out += "[" + part + "]";
    else out += (out.empty() ? "" : ".") + part;
  }
  return out;
}

std::string SceneDesc::missing_entry(const std::string& path) const {
  const auto lb = path.find('[');
  if (lb == std::string::npos) return "";
  const std::string group = path.substr(0, lb);
  const auto rb = path.find(']', lb);
  const std::string digits = path.substr(lb + 1, rb == std::string::npos ? std::string::npos : rb - lb - 1);
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
    return "'" + path + "': the index of " + group + "[...] must be a whole number";
  // ([00] named no entry, and was "set but not used")
  const size_t first = std::min(digits.find_first_not_of('0'), digits.size() - 1);
  if (first > 0)
    return "'" + path + "': write the index of " + group + "[...] without leading zeros (" + group + "[" +
           digits.substr(first) + "])";
  if (digits.size() > 9)
    return "no " + group + "[" + digits + "] in the scene (it has " + std::to_string(group_count(group)) + ")";
  const int index = std::stoi(digits);
  if (index < group_count(group)) return "";
  return "no " + group + "[" + std::to_string(index) + "] in the scene (it has " + std::to_string(group_count(group)) +
         ")";
}

void apply_override(SceneDesc& desc, const Override& o) { apply_override_at(desc, o, 1, false); }

Override parse_override(const std::string& key_eq_value) {
  const auto eq = key_eq_value.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(FileLoc{"--set", 0, 0}, "expected KEY=VALUE, got '" + key_eq_value + "'");
  return Override{key_eq_value.substr(0, eq), key_eq_value.substr(eq + 1)};
}

SceneDesc parse_scene(const std::string& text, const std::string& name, const std::vector<Override>& overrides) {
  SceneDesc desc;
  desc.file = name;
  desc.text = text;
  toml::table root;
  // A byte that is no UTF-8 at its own line and column (the parser's report pointed before it).
  if (const size_t bad = first_invalid_utf8(text); bad != std::string::npos) {
    int line = 1, col = 1;  // the column in characters, as the parser counts
    for (size_t k = 0; k < bad; ++k) {
      if (text[k] == '\n') line += 1, col = 1;
      else if ((static_cast<unsigned char>(text[k]) & 0xC0) != 0x80) ++col;
    }
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(text[bad]));
    throw SceneError(FileLoc{name, line, col},
                     std::string("invalid UTF-8 (byte ") + hex + "): a scene file is UTF-8 text");
  }
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw parse_error(e, name);
  }
  Literals literals(text);
  refuse_underflow(root, literals, [&](const toml::node& n) { return loc_of(n.source(), name); });
  Reader(desc, name).table(root, "");
  int ordinal = 1;
  for (const Override& o : overrides) apply_override_at(desc, o, ordinal++, true);
  return desc;
}

SceneDesc load_scene_file(const std::string& path, const std::vector<Override>& overrides) {
  check_input_file(path, "scene file", kMaxTextFileBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read scene file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path, overrides);
}

}  // namespace silt
