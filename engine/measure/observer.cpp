// Observable names -> values, from the tables of the modules a scene enables (ModuleSpec).
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt {
namespace {

const char* kAxes = "xyz";

// Matches `name` against a pattern with placeholders ({a}, {b}, {w}, {k}); fills args.
bool match(const std::string& pattern, const std::string& name, int dim, ObservableArgs& args) {
  size_t p = 0, n = 0;
  while (p < pattern.size()) {
    if (pattern[p] == '{' && p + 2 < pattern.size() && pattern[p + 2] == '}') {
      const char ph = pattern[p + 1];
      p += 3;
      if (ph == 'k') {
        size_t e = n;
        while (e < name.size() && e - n < 11 && name[e] >= '0' && name[e] <= '9') ++e;
        if (e == n) return false;
        args.k = std::stoll(name.substr(n, e - n));
        n = e;
        continue;
      }
      if (n >= name.size()) return false;
      const char* at = std::strchr(kAxes, name[n]);
      if (!at || !*at) return false;
      const int axis = static_cast<int>(at - kAxes);
      if (ph == 'a' || ph == 'b') {
        if (axis >= dim) return false;
        (ph == 'a' ? args.a : args.b) = axis;
      } else if (ph == 'w') {
        if (dim == 2 && axis != 2) return false;  // a disk turns about z only
        args.w = dim == 2 ? 0 : axis;
      } else {
        return false;
      }
      ++n;
      continue;
    }
    if (n >= name.size() || name[n] != pattern[p]) return false;
    ++p;
    ++n;
  }
  return n == name.size();
}

// Every name a pattern stands for in this model, with the indices it lists.
std::vector<std::string> expand(const ObservableSpec& o, const Model& m) {
  std::vector<std::string> out{""};
  const std::string& pat = o.pattern;
  for (size_t p = 0; p < pat.size();) {
    std::vector<std::string> choices;
    if (pat[p] == '{' && p + 2 < pat.size() && pat[p + 2] == '}') {
      const char ph = pat[p + 1];
      if (ph == 'k') {
        const int64_t count = o.k_count ? std::min(o.k_count(m), o.k_listed) : o.k_listed;
        for (int64_t k = 0; k < count; ++k) choices.push_back(std::to_string(k));
      } else if (ph == 'w' && m.dim == 2) {
        choices.push_back("z");
      } else {
        const int axes = ph == 'w' ? 3 : m.dim;
        for (int k = 0; k < axes; ++k) choices.push_back(std::string(1, kAxes[k]));
      }
      p += 3;
    } else {
      choices.push_back(std::string(1, pat[p]));
      ++p;
    }
    std::vector<std::string> next;
    for (const std::string& head : out)
      for (const std::string& c : choices) next.push_back(head + c);
    out = std::move(next);
  }
  return out;
}

// Names in the contract whose module this version does not have (INTERFACE.md).
bool needs_other_module(const std::string& name) {
  static const char* later[] = {"Vi", "mobilisation", "p_cont_ratio", "p_lub_ratio", "eta_eff"};
  return std::any_of(std::begin(later), std::end(later), [&](const char* s) { return name == s; });
}

struct Found {
  const ObservableSpec* spec = nullptr;
  ObservableArgs args;
  std::string error;
};

// An observable's own words for why it does not apply, with its name when they do not say it.
std::string named(const std::string& name, const std::string& why) {
  if (why.empty() || why.find("'" + name + "'") != std::string::npos) return why;
  return "observable '" + name + "': " + why;
}

Found find(const std::string& name, const Model& m) {
  Found f;
  std::string off_error;  // the first match in a module the scene does not enable
  for (const Module& mod : modules())
    for (const ObservableSpec& o : mod.spec->observables) {
      ObservableArgs args;
      if (!match(o.pattern, name, m.dim, args)) continue;
      if (!m.module_on(mod.spec->name)) {
        // Another module may provide the same name (solver.iters: the paste's or the fluid's);
        // else the observable's own words when it has them ("applies where the scene shears").
        if (!off_error.empty()) continue;
        off_error = o.check ? named(name, o.check(m, args)) : std::string();
        if (off_error.empty())
          off_error = "observable '" + name + "' does not apply to this scene (it needs the " + mod.spec->name +
                      " module, which the scene does not enable)";
        continue;
      }
      if (o.k_count && args.k >= o.k_count(m)) {
        f.error = "'" + name + "': there is no " + o.k_what + " " + std::to_string(args.k) + " (the scene has " +
                  std::to_string(o.k_count(m)) + ")";
        return f;
      }
      if (o.check)
        if (std::string why = o.check(m, args); !why.empty()) {
          f.error = named(name, why);
          return f;
        }
      f.spec = &o;
      f.args = args;
      return f;
    }
  if (!off_error.empty()) {
    f.error = off_error;
    return f;
  }
  if (needs_other_module(name)) {
    f.error = "observable '" + name + "' does not apply to this scene (it needs a module the scene does not enable)";
    return f;
  }
  // A name of the other dimension (stress.zz, p[0].z in 2D) was "unknown", though documented.
  for (const Module& mod : modules())
    for (const ObservableSpec& o : mod.spec->observables) {
      ObservableArgs args;
      if (!match(o.pattern, name, m.dim == 2 ? 3 : 2, args)) continue;
      f.error = "observable '" + name + "' is of a " + (m.dim == 2 ? "3D" : "2D") + " scene, and this one is " +
                std::to_string(m.dim) + "D";
      return f;
    }
  f.error = "unknown observable '" + name + "'";
  std::string best;
  size_t best_d = 3;
  for (const std::string& c : observable_names(m)) {
    const size_t dist = edit_distance(name, c, best_d);
    if (dist < best_d) {
      best_d = dist;
      best = c;
    }
  }
  if (!best.empty()) f.error += "; did you mean '" + best + "'?";
  return f;
}

// Whether the model takes `name`, one of o's expanded names (its check passes).
bool accepts(const ObservableSpec& o, const Model& m, const std::string& name) {
  if (!o.check) return true;
  ObservableArgs args;
  match(o.pattern, name, m.dim, args);
  return o.check(m, args).empty();
}

}  // namespace

const Measurements& ObservableContext::meas(unsigned parts) const {
  const unsigned missing = parts & ~measured_;
  if (missing) measure_into(m, s, missing, meas_);
  // (the skeleton's pass measures the contacts too)
  measured_ |= missing | ((missing & measure_part::kSkeleton) ? measure_part::kContacts : 0U);
  return meas_;
}

int64_t ObservableContext::index_of(int64_t id) const {
  if (index_.empty()) index_ = index_of_ids(s);
  return index_[id];
}

std::string check_observable(const std::string& name, const Model& m) { return find(name, m).error; }

bool observable_of_last_step(const std::string& name, const Model& m) {
  const Found f = find(name, m);
  return f.spec && f.spec->of_last_step;
}

std::vector<std::pair<std::string, std::string>> observable_units(const Model& m) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Module& mod : modules()) {
    if (!m.module_on(mod.spec->name)) continue;
    for (const ObservableSpec& o : mod.spec->observables)
      for (const std::string& name : expand(o, m))
        if (accepts(o, m, name)) out.emplace_back(name, m.unit_name(o.unit));
  }
  return out;
}

std::vector<ObservableDoc> observable_docs(const Model* m) {
  std::vector<ObservableDoc> out;
  for (const Module& mod : modules()) {
    if (m && !m->module_on(mod.spec->name)) continue;
    for (const ObservableSpec& o : mod.spec->observables) {
      // For a model, not those it refuses (gamma without a shear): none of their names passes.
      if (m && o.check) {
        const std::vector<std::string> names = expand(o, *m);
        if (!names.empty() &&
            std::none_of(names.begin(), names.end(), [&](const std::string& n) { return accepts(o, *m, n); }))
          continue;
      }
      std::string name = o.pattern;
      for (const auto& [from, to] :
           {std::pair<std::string, std::string>{"{a}", "A"}, {"{b}", "B"}, {"{k}", "K"}, {"{w}", "W"}})
        for (auto at = name.find(from); at != std::string::npos; at = name.find(from))
          name.replace(at, from.size(), to);
      out.push_back({name, m ? m->unit_name(o.unit) : o.unit, o.doc, mod.spec->name});
    }
  }
  return out;
}

std::vector<std::string> observable_names(const Model& m) {
  std::vector<std::string> out;
  for (auto& [name, unit] : observable_units(m)) out.push_back(name);
  return out;
}

Observer::Observer(const Model& m, std::vector<std::string> names) : names_(std::move(names)) {
  if (names_.empty()) throw std::invalid_argument("no observable to sample: give at least one");
  for (const std::string& n : names_) {
    if (std::count(names_.begin(), names_.end(), n) > 1) throw std::invalid_argument("'" + n + "' is listed twice");
    Found f = find(n, m);
    if (!f.spec) throw std::invalid_argument(f.error);
    items_.push_back({f.spec, f.args});
    units_.push_back(m.unit_name(f.spec->unit));
  }
}

std::vector<double> Observer::sample(const Model& m, const State& s) const {
  const ObservableContext ctx(m, s);
  std::vector<double> out;
  out.reserve(items_.size());
  for (const Item& it : items_) out.push_back(it.spec->value(ctx, it.args));
  return out;
}

}  // namespace silt
