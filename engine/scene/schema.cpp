// The single source of truth for every scene key (DESIGN.md "Parameters, scene files, errors"):
// the keys the modules declare (silt/module.hpp). The reader validates against it, compile()
// reads defaults from it, `silt params` and the README's parameter table print it.
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "silt/module.hpp"
#include "silt/scene.hpp"

namespace silt {
namespace {

// The keys and rules of every module, assembled once each module is known (modules registered
// later are appended: the deque keeps earlier keys where they are).
struct Assembled {
  std::deque<KeySpec> keys;
  std::vector<KeyRule> rules;
  size_t modules = 0;
};

Assembled& assembled() {
  static Assembled a;
  const auto& list = modules();
  while (a.modules < list.size()) {
    const ModuleSpec& spec = *list[a.modules++].spec;
    for (KeySpec k : spec.keys) {
      for (const KeySpec& other : a.keys)
        if (other.path == k.path) throw std::logic_error("scene key " + k.path + " declared by two modules");
      k.module = spec.name;
      a.keys.push_back(std::move(k));
    }
    a.rules.insert(a.rules.end(), spec.rules.begin(), spec.rules.end());
  }
  return a;
}

}  // namespace

const std::deque<KeySpec>& scene_schema() { return assembled().keys; }
const std::vector<KeyRule>& scene_rules() { return assembled().rules; }

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  if (lo_open ? !(x > lo) : !(x >= lo)) return false;
  if (hi_open ? !(x < hi) : !(x <= hi)) return false;
  return true;
}

static std::string num(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

std::string Range::str() const {
  const bool has_lo = lo > -1e307, has_hi = hi < 1e307;
  if (has_lo && has_hi) return (lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
  if (has_lo) return (lo_open ? "> " : ">= ") + num(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + num(hi);
  return "any";
}

const char* key_type_name(KeyType t) {
  switch (t) {
    case KeyType::kBool: return "boolean";
    case KeyType::kInt: return "integer";
    case KeyType::kReal: return "number";
    case KeyType::kString: return "string";
    case KeyType::kRealList: return "list of numbers";
    case KeyType::kRealMatrix: return "list of lists of numbers";
    case KeyType::kBoolList: return "list of booleans";
    case KeyType::kStringList: return "list of strings";
  }
  return "?";
}

namespace {

// What both listings show of a key beside its name, type, unit and liveness.
struct KeyColumns {
  std::string def;    // "" when none
  std::string range;  // "" for a key that is not numeric
  std::string doc;    // with the choices of a string key
};

KeyColumns key_columns(const KeySpec& k, const char* quote) {
  KeyColumns c;
  c.doc = k.doc;
  if (!k.choices.empty()) {
    c.doc += " One of:";
    for (const auto& choice : k.choices) c.doc += std::string(" ") + quote + choice + quote;
    c.doc += ".";
  }
  if (k.def) c.def = quote + value_to_string(*k.def) + quote;
  if (k.type == KeyType::kInt || k.type == KeyType::kReal || k.type == KeyType::kRealList) c.range = k.range.str();
  return c;
}

}  // namespace

std::string schema_markdown() {
  std::ostringstream o;
  o << "| key | module | type | default | range | unit | live | meaning |\n|---|---|---|---|---|---|---|---|\n";
  for (const KeySpec& k : scene_schema()) {
    const KeyColumns c = key_columns(k, "`");
    o << "| `" << k.path << "` | " << k.module << " | " << key_type_name(k.type) << " | "
      << (c.def.empty() ? std::string("-") : c.def) << " | " << c.range << " | " << k.unit << " | "
      << (k.steerable ? "yes" : "") << " | " << c.doc << " |\n";
  }
  return o.str();
}

std::string schema_text() {
  // (it listed the type and unit alone, where `silt params --help` promises defaults and ranges)
  std::ostringstream o;
  for (const KeySpec& k : scene_schema()) {
    const KeyColumns c = key_columns(k, "");
    o << k.path << "  (" << key_type_name(k.type) << (k.unit.empty() ? "" : ", " + k.unit)
      << (k.steerable ? ", live" : "") << "; default " << (c.def.empty() ? std::string("none") : c.def)
      << (c.range.empty() ? "" : "; range " + c.range) << ")  " << c.doc << "\n";
  }
  return o.str();
}

}  // namespace silt
