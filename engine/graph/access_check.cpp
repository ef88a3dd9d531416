#include "graph/access_check.hpp"

#include <algorithm>
#include <stdexcept>

namespace silt::graph {
namespace {

bool declared(const Access& a, FieldId f) { return std::find(a.begin(), a.end(), f) != a.end(); }

// Other values of the same kind: a stage that reads them computes something else.
void poison(double& x) { x = 1.25 * x + 0.0625; }
void poison(bool& x) { x = !x; }
void poison(int64_t& x) { x ^= 7; }  // (+ 7 overflowed on a checkpoint's largest count)
void poison(Vec3a& v) {
  for (double& x : v) poison(x);
}
void poison(Box& b) {
  for (int k = 0; k < 3; ++k) {
    poison(b.lo[k]);
    poison(b.len[k]);
  }
  poison(b.le_offset);
}
void poison(std::vector<double>& v) {
  for (double& x : v) poison(x);
}
// Poisons field `id` of s; false for integer arrays (indices), which are left alone.
bool poison_field(State& s, FieldId id) {
  bool done = false;
  for_each_field(s, [&](const FieldInfo& f, auto& v) {
    if constexpr (requires { poison(v); }) {
      if (f.id != id) return;
      poison(v);
      done = true;
    }
  });
  return done;
}

// Runs the stage on a copy; false when it threw.
bool run_on(const Stage& st, const Model& m, State& c) {
  try {
    st.fn(m, c);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

void run_checked(const Stage& st, const Model& m, State& s) {
  const std::vector<uint64_t> before = field_hashes(s);
  if (st.carries_workspace) {  // one run: its writes checked, not its reads
    st.fn(m, s);
    const std::vector<uint64_t> after = field_hashes(s);
    for (size_t f = 0; f < before.size(); ++f)
      if (before[f] != after[f] && !declared(st.writes, static_cast<FieldId>(f)))
        throw std::logic_error("access check: stage " + st.name + " writes field " +
                               field_info(static_cast<FieldId>(f)).name + ", which its access set does not declare");
    return;
  }
  const State pristine = s;
  const size_t n = before.size();
  std::vector<FieldId> poisoned;
  State copy = pristine;
  for (size_t f = 0; f < n; ++f) {
    const auto id = static_cast<FieldId>(f);
    if (!declared(st.reads, id) && poison_field(copy, id)) poisoned.push_back(id);
  }
  const bool copy_ran = run_on(st, m, copy);
  st.fn(m, s);  // the real run; its exceptions are the stage's own
  const std::vector<uint64_t> after = field_hashes(s);
  for (size_t f = 0; f < n; ++f) {
    const auto id = static_cast<FieldId>(f);
    if (before[f] != after[f] && !declared(st.writes, id))
      throw std::logic_error("access check: stage " + st.name + " writes field " + field_info(id).name +
                             ", which its access set does not declare");
  }
  auto differs = [&](const State& c, bool ran) {
    if (!ran) return true;
    for (FieldId w : st.writes)
      if (w < n && field_hash(c, w) != after[w]) return true;
    return false;
  };
  if (!differs(copy, copy_ran)) return;
  for (FieldId id : poisoned) {
    State c = pristine;
    poison_field(c, id);
    if (differs(c, run_on(st, m, c)))
      throw std::logic_error(
          "access check: stage " + st.name + " reads field " + field_info(id).name +
          ", which its access set does not declare" +
          (declared(st.writes, id) ? " (it writes it: a stage that leaves part of a field as it was reads it)" : ""));
  }
  throw std::logic_error("access check: stage " + st.name +
                         " gives other results when the fields it does not read change (several of them together)");
}

}  // namespace silt::graph
