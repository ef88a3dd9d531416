// The shell's commands on the state itself: its fields, read from the field list (silt/fields.hpp),
// and freezing grains.
#include <algorithm>
#include <cmath>

#include "shell/session.hpp"
#include "shell/table.hpp"
#include "silt/text.hpp"

namespace silt::shell {
namespace {

// A value of a field's element, as text.
template <class T>
std::string text_of(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_same_v<T, Box>) {
    std::string out = "lo (";
    for (int k = 0; k < 3; ++k) out += (k ? ", " : "") + format_number(v.lo[k], 10);
    out += "), lengths (";
    for (int k = 0; k < 3; ++k) out += (k ? ", " : "") + format_number(v.len[k], 10);
    return out + "), Lees-Edwards offset " + format_number(v.le_offset, 10);
  } else if constexpr (std::is_same_v<T, Vec3a>) {
    return "(" + format_number(v[0], 10) + ", " + format_number(v[1], 10) + ", " + format_number(v[2], 10) + ")";
  } else {
    return format_number(static_cast<double>(v), 10);
  }
}

}  // namespace

void Session::cmd_fields(const Command& c) {
  const std::string prefix = c.args.empty() ? "" : c.args[0].text;
  Table t({"field", "module", "extent", "type", "entries", "bytes", "unit", "meaning"},
          {false, false, false, false, true, true, false, false});
  at_boundary([&] {
    for_each_field(sim().state(), [&](const FieldInfo& f, const auto& v) {
      if (f.name.rfind(prefix, 0) != 0) return;
      size_t entries = 1, bytes = sizeof(v);
      if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
        entries = v.size();
        bytes = v.capacity() * sizeof(v[0]);
      }
      t.add({f.name, f.module, extent_name(f.extent), f.type, std::to_string(entries), std::to_string(bytes), f.unit,
             f.doc});
    });
  });
  if (t.rows() == 0) throw std::runtime_error("no field starts with '" + prefix + "'");
  t.print(out_);
}

void Session::cmd_field(const Command& c) {
  const FieldInfo* info = find_field(c.args[0].text);
  if (!info) {
    std::string best;
    size_t best_d = 4;
    for (const FieldInfo& f : field_infos())
      if (const size_t d = edit_distance(c.args[0].text, f.name, best_d); d < best_d) {
        best_d = d;
        best = f.name;
      }
    throw std::runtime_error("no field '" + c.args[0].text + "'" +
                             (best.empty() ? "" : "; did you mean '" + best + "'?"));
  }
  std::optional<int64_t> k;
  if (c.args.size() == 2) {
    k = parse_count(c.args[1].text, 0);
    if (!k) throw ParseError(c.args[1].col, "K is an index: a whole number from 0");
  }
  std::string line;
  at_boundary([&] {
    const State& s = sim().state();
    for_each_field(s, [&](const FieldInfo& f, const auto& v) {
      if (f.id != info->id) return;
      using V = std::remove_cvref_t<decltype(v)>;
      if constexpr (!kIsArray<V>) {
        line = f.name + " = " + text_of(v) + (f.unit.empty() ? "" : " " + f.unit);
      } else {
        // Entries per item: a vector per grain or pair, one per wall of a grain.
        int64_t per = 1;
        if (f.extent == Extent::kGrainVec || f.extent == Extent::kPairVec) per = s.dim;
        if (f.extent == Extent::kGrainRot || f.extent == Extent::kGrainRotWalls) per = s.rot;
        if (f.extent == Extent::kGrainWallVec) per = int64_t{s.dim} * s.n_walls;
        if (k) {
          int64_t at = *k;
          if (follows_grains(f.extent)) {
            if (at >= s.n) throw std::runtime_error("there is no grain " + std::to_string(at));
            at = index_of_ids(s)[at];
          }
          if (at >= static_cast<int64_t>(v.size()) / std::max<int64_t>(per, 1))  // ((at + 1) per overflowed)
            throw std::runtime_error(f.name + " has " + std::to_string(v.size() / std::max<int64_t>(per, 1)) +
                                     " entries");
          line = f.name + "[" + std::to_string(*k) + "] =";
          for (int64_t q = 0; q < per; ++q) line += " " + text_of(v[at * per + q]);
          line += f.unit.empty() ? "" : " " + f.unit;
        } else if (v.empty()) {
          line = f.name + ": no entry";
        } else {
          double lo = 1e308, hi = -1e308, sum = 0;
          for (const auto& x : v) {
            lo = std::min(lo, static_cast<double>(x));
            hi = std::max(hi, static_cast<double>(x));
            sum += static_cast<double>(x);
          }
          line = f.name + ": " + std::to_string(v.size()) + " entries (" + extent_name(f.extent) + "), from " +
                 format_number(lo) + " to " + format_number(hi) + ", mean " + format_number(sum / v.size()) +
                 (f.unit.empty() ? "" : " " + f.unit);
        }
      }
    });
  });
  out_ << line << "\n";
}

void Session::cmd_freeze(const Command& c) {
  const std::string& axis = c.args[0].text;
  const std::string& op = c.args[1].text;
  if (axis.size() != 1 || axis[0] < 'x' || axis[0] > 'z') throw ParseError(c.args[0].col, "AXIS is x, y or z");
  if (op != "<" && op != ">") throw ParseError(c.args[1].col, "usage: freeze AXIS < VALUE | freeze AXIS > VALUE");
  const std::optional<double> value = parse_number(c.args[2].text);
  if (!value) throw ParseError(c.args[2].col, "VALUE is a number");
  require_stopped("cannot freeze grains");
  Simulation& s = sim();
  int64_t n = 0;
  try {
    n = s.freeze(axis[0] - 'x', op == "<", *value);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("freeze: ") + e.what());
  }
  out_ << "froze " << n << " grain(s): " << s.model().n_frozen << " of " << s.model().n_grains
       << " frozen; a checkpoint saved now makes a base ([[grains]] frozen_from = FILE)\n";
}

}  // namespace silt::shell
