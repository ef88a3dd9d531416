// Checkpoint file layout (little-endian, version 5):
//   "SILTCKPT" | u32 version | system | scene | fields | u64 FNV-1a of all before it
//   system: u64 fingerprint (compile.cpp) | i32 dim | i64 n | u8 periodic[3] | u32 walls |
//           per wall f64 point[3], f64 normal[3]
//   scene:  str name | u32 count | count x (str key, str value)     str: u32 length, bytes
// The system decides whether a checkpoint can be restored: a state belongs to its grains, walls and
// periodicity, and is refused elsewhere with what differs. The scene part, every parameter's
// resolved value, only informs: a prepared packing is meant to be restored under other run
// parameters, and the values that differ (steered ones, say) are reported.
//   fields: every field of State in the order of its field list (silt/fields.hpp), module fields
//           last: str name | u32 element size | u64 count | bytes. A scalar is one element whose
//           size is that of its bytes (a Box member by member). A field added to the list is
//           saved without touching this file. Module fields are read back by name, so a file
//           written before a module existed (its fields absent) still reads.
// On reading, every array's length is checked against the state's dimensions, every index
// against its range and every floating-point value for finiteness: a file that passes the
// checksum but not these is corrupt. The file is written to a new temporary file beside PATH
// (make_temp_beside), flushed to disk, renamed over PATH and the directory flushed: a crash or a kill during the write
// keeps the previous file, and a crash after it keeps the new one.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/rng.hpp"
#include "io/checkpoint_file.hpp"
#include "silt/io.hpp"
#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt {
namespace {

using ckpt::get_system;
using ckpt::put_system;
using ckpt::Reader;
using ckpt::System;
using ckpt::Writer;

System system_of(const Model& m) {
  System y{m.scene_hash, m.dim, m.n_grains, {}, {}};
  for (int k = 0; k < 3; ++k) y.periodic[k] = m.box.periodic[k];
  for (const Wall& w : m.walls)
    y.walls.push_back({w.point[0], w.point[1], w.point[2], w.normal[0], w.normal[1], w.normal[2]});
  return y;
}

std::string axes(const std::array<uint8_t, 3>& periodic, int dim) {
  std::string out;
  for (int k = 0; k < dim; ++k)
    if (periodic[k]) out += std::string(out.empty() ? "" : " ") + "xyz"[k];
  return out.empty() ? "no axis" : out;
}

std::string wall_text(const std::array<double, 6>& w, int dim) {
  auto vec = [&](int at) {
    std::string s = "(";
    for (int k = 0; k < dim; ++k) s += (k ? ", " : "") + format_number(w[at + k]);
    return s + ")";
  };
  return "point " + vec(0) + ", normal " + vec(3);
}

// What differs between the system of a checkpoint and the scene's, "" when nothing.
std::string difference(const System& saved, const System& now) {
  auto both = [](const std::string& a, const std::string& b) {
    return a + " in the checkpoint, " + b + " in the scene";
  };
  if (saved.dim != now.dim) return both("dimension " + std::to_string(saved.dim), std::to_string(now.dim));
  if (saved.n != now.n) return both(std::to_string(saved.n) + " grains", std::to_string(now.n));
  if (saved.periodic != now.periodic)
    return both("periodic along " + axes(saved.periodic, saved.dim), axes(now.periodic, now.dim));
  if (saved.walls.size() != now.walls.size())
    return both(std::to_string(saved.walls.size()) + " wall(s)", std::to_string(now.walls.size()));
  for (size_t k = 0; k < now.walls.size(); ++k)
    if (saved.walls[k] != now.walls[k])
      return "wall " + std::to_string(k) + ": " +
             both(wall_text(saved.walls[k], saved.dim), wall_text(now.walls[k], now.dim));
  return "";  // the grains themselves are compared once the state is read (grains_difference)
}

// What differs between the grains of a checkpoint (its fingerprint and its state's frozen flags)
// and the scene's, "" when nothing. `freed` counts the grains frozen in the scene and free in the
// checkpoint, `frozen` (by grain id) the grains frozen in the checkpoint and free in the scene.
std::string grains_difference(uint64_t saved, const State& s, const Model& m, std::vector<uint8_t>& frozen,
                              int64_t& freed) {
  freed = 0;
  frozen.assign(m.init.frozen.size(), 0);
  if (saved == m.scene_hash) return "";
  std::vector<uint8_t> flags(m.init.frozen.size(), 0);
  for (int64_t i = 0; i < s.n; ++i) flags[s.particle_id[i]] = s.particle_frozen[i];
  if (system_fingerprint(m, flags) != saved) return "the grains differ (sizes, masses or groups)";
  int64_t more = 0;
  for (size_t id = 0; id < flags.size(); ++id) {
    frozen[id] = flags[id] && !m.init.frozen[id];
    more += frozen[id];
    freed += !flags[id] && m.init.frozen[id];
  }
  std::string why = "the grains are the scene's, but ";
  if (more) why += std::to_string(more) + " of them are frozen in the checkpoint and free in the scene";
  if (more && freed) why += ", and ";
  if (freed) why += std::to_string(freed) + " frozen in the scene are free in the checkpoint";
  return why;
}

// The parameters of the checkpoint that differ from the scene's, as warnings.
std::vector<std::string> parameter_differences(const std::vector<std::pair<std::string, std::string>>& saved,
                                               const std::vector<std::pair<std::string, std::string>>& now) {
  std::map<std::string, std::pair<std::string, std::string>> both;  // key -> (checkpoint, scene)
  for (const auto& [key, value] : saved) both[key].first = value;
  for (const auto& [key, value] : now) both[key].second = value;
  std::vector<std::string> out;
  for (const auto& [key, values] : both) {
    if (values.first == values.second) continue;
    auto shown = [](const std::string& v) { return v.empty() ? std::string("(not set)") : v; };
    out.push_back(key + " = " + shown(values.first) + " in the checkpoint, " + shown(values.second) + " in the scene");
  }
  return out;
}

// Flushes the directory holding `path`, so that a rename in it survives a crash.
void sync_directory(const std::string& path) {
  std::string dir = std::filesystem::path(path).parent_path().string();
  if (dir.empty()) dir = ".";
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;  // the file itself is in place; only its durability across a crash is at stake
  ::fsync(fd);
  ::close(fd);
}

// Whether the bools of a scalar field read from a file are 0 or 1: loading any other byte as a bool
// is undefined behaviour, so they are looked at as bytes before anything reads the value.
bool bool_bytes(const bool* b, size_t n) {
  for (size_t k = 0; k < n; ++k) {
    unsigned char c = 0;
    std::memcpy(&c, b + k, 1);
    if (c > 1) return false;
  }
  return true;
}
template <class T>
bool bools_valid(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return bool_bytes(&v, 1);
  else if constexpr (std::is_same_v<T, Box>)
    return bool_bytes(v.periodic.data(), v.periodic.size()) && bool_bytes(&v.lees_edwards, 1);
  else return true;
}

// Whether every floating-point number of a scalar field is finite (integers and flags are).
bool finite_value(double x) { return std::isfinite(x); }
bool finite_value(const Vec3a& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
bool finite_value(const Box& b) { return finite_value(b.lo) && finite_value(b.len) && std::isfinite(b.le_offset); }
template <class T>
bool finite_value(const T&) {
  return true;
}

// "" when the state is one a simulation of m can hold: every array as long as its extent says,
// every index in range, every floating-point value finite; else what is wrong.
std::string check_state(const State& s, const Model& m) {
  const int64_t n = s.n;
  if (static_cast<int64_t>(s.nbr_start.size()) != n + 1)
    return "nbr_start has " + std::to_string(s.nbr_start.size()) + " entries, not N + 1";
  const int64_t np = s.n_pairs();
  std::string bad;
  for_each_field(s, [&](const FieldInfo& f, const auto& v) {
    if (!bad.empty()) return;
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
      const bool on = f.id < fid::kBuiltinCount || m.module_on(f.module);
      const int64_t want = on ? extent_size(s, f.extent) : 0;
      // A free-length array is checked by its module (below).
      if (static_cast<int64_t>(v.size()) != want && !(on && f.extent == Extent::kFree)) {
        bad = f.name + " has " + std::to_string(v.size()) + " entries where " + std::to_string(want) +
              " are expected (" + extent_name(f.extent) + ")";
        return;
      }
      if constexpr (std::is_same_v<std::decay_t<decltype(v[0])>, double>)
        for (size_t k = 0; k < v.size(); ++k)
          if (!std::isfinite(v[k])) {
            bad = f.name + "[" + std::to_string(k) + "] is not finite";
            return;
          }
    } else if constexpr (std::is_same_v<std::remove_cvref_t<decltype(v)>, int64_t>) {
      // A count (steps, list builds): one at 2^63 - 1 overflowed at the first step that added to it.
      if (v < 0 || v > kMaxRunSteps)
        bad = f.name + " = " + std::to_string(v) + " is outside [0, " + kMaxRunStepsText + "]";
    } else if (!finite_value(v)) {
      bad = f.name + " is not finite";
    }
  });
  if (!bad.empty()) return bad;
  if (s.nbr_start[0] != 0 || s.nbr_start[n] != np) return "nbr_start does not span the pair list";
  // Every row bound first: from 0 to np without decreasing, each is within the list before any
  // row's pairs are read (a row may otherwise end past the list, a later one coming back).
  for (int64_t i = 0; i < n; ++i)
    if (s.nbr_start[i + 1] < s.nbr_start[i]) return "nbr_start decreases at row " + std::to_string(i);
  for (int64_t i = 0; i < n; ++i) {
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p)
      if (s.pair_i[p] != i || s.pair_j[p] <= i || s.pair_j[p] >= n)
        return "pair " + std::to_string(p) + " is not a pair of row " + std::to_string(i);
  }
  std::vector<uint8_t> seen(n, 0);
  for (int64_t i = 0; i < n; ++i) {
    const int32_t id = s.particle_id[i];
    if (id < 0 || id >= n || seen[id]) return "particle_id is not a numbering of the grains";
    seen[id] = 1;
    if (s.particle_group[i] < 0 ||
        s.particle_group[i] >= static_cast<int32_t>(std::max<size_t>(1, m.group_names.size())))
      return "particle_group[" + std::to_string(i) + "] is not a group of the scene";
    if (s.particle_frozen[i] > 1) return "particle_frozen[" + std::to_string(i) + "] is neither 0 nor 1";
  }
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(s.box.lo[k]) || !(s.box.len[k] > 0) || !std::isfinite(s.box.len[k]))
      return "the box is not finite";
  if (!(s.box.le_offset >= 0 && s.box.le_offset <= s.box.len[0])) return "the Lees-Edwards offset is outside [0, L_x]";
  if (!std::isfinite(s.t) || !std::isfinite(s.dt)) return "the time is not finite";
  // What the modules keep of their own (a free-length array).
  for (const Module& mod : modules())
    if (mod.spec->check_state && m.module_on(mod.spec->name))
      if (std::string why = mod.spec->check_state(m, s); !why.empty()) return why;
  return "";
}

}  // namespace

std::vector<std::pair<std::string, std::string>> scene_parameters(const SceneDesc& d) {
  std::vector<std::pair<std::string, std::string>> out;
  auto add = [&](const std::string& key, const KeySpec& spec) {
    std::string value;
    if (auto it = d.entries.find(key); it != d.entries.end()) value = value_to_string(it->second.value);
    else if (spec.def) value = value_to_string(*spec.def);
    out.emplace_back(key, value);
  };
  for (const KeySpec& k : scene_schema()) {
    const auto br = k.path.find("[]");
    if (br == std::string::npos) {
      add(k.path, k);
      continue;
    }
    const std::string group = k.path.substr(0, br);
    for (int i = 0; i < d.group_count(group); ++i)
      add(group + "[" + std::to_string(i) + "]" + k.path.substr(br + 2), k);
  }
  return out;
}

void write_checkpoint(const std::string& path, const Model& m, const State& s) {
  check_output_path(path, "checkpoint", true);
  Writer w;
  w.bytes(ckpt::kMagic, sizeof ckpt::kMagic);
  w.put(ckpt::kVersion);
  put_system(w, system_of(m));
  w.str(m.scene_name);
  const auto params = scene_parameters(m.desc);
  w.put(static_cast<uint32_t>(params.size()));
  for (const auto& [key, value] : params) {
    w.str(key);
    w.str(value);
  }
  w.put(static_cast<uint32_t>(field_infos().size()));
  for_each_field(s, [&](const FieldInfo& f, const auto& v) {
    w.str(f.name);
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
      w.put(static_cast<uint32_t>(sizeof(v[0])));
      w.put(static_cast<uint64_t>(v.size()));
      if (!v.empty()) w.bytes(v.data(), v.size() * sizeof(v[0]));
    } else {
      std::vector<char> blob;
      field_bytes(v, [&](const void* p, size_t n) {
        blob.insert(blob.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
      });
      w.put(static_cast<uint32_t>(blob.size()));
      w.put(uint64_t{1});
      w.bytes(blob.data(), blob.size());
    }
  });
  const uint64_t sum = fnv1a(w.buf_.data(), w.buf_.size());
  w.put(sum);
  const TempFile temp = make_temp_beside(path);
  const std::string& tmp = temp.name;
  const int fd = temp.fd;
  if (fd < 0) throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(errno));
  size_t done = 0;
  while (done < w.buf_.size()) {
    const ssize_t k = ::write(fd, w.buf_.data() + done, w.buf_.size() - done);
    if (k < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(error));
    }
    done += static_cast<size_t>(k);
  }
  // The bytes reach the disk before the name does: a crash then leaves the old file or the new one.
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const int error = errno;
    ::unlink(tmp.c_str());
    throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(error));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(tmp.c_str());
    throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(error));
  }
  sync_directory(path);
}

State read_checkpoint(const std::string& path, const Model& m, std::vector<std::string>* differences,
                      std::vector<uint8_t>* frozen) {
  const std::vector<char> buf = ckpt::read_checked(path);
  Reader r = ckpt::body(buf, path);
  const System saved = get_system(r);
  if (const std::string diff = difference(saved, system_of(m)); !diff.empty())
    throw IoError("checkpoint '" + path + "' was written for a different system: " + diff);
  r.str();  // the scene's name, also among the parameters (scene.name)
  std::vector<std::pair<std::string, std::string>> params(r.count(8));  // two lengths each
  for (auto& [key, value] : params) {
    key = r.str();
    value = r.str();
  }
  std::vector<std::string> changed = parameter_differences(params, scene_parameters(m.desc));
  // A fluid's fields are read on the scene's grid: a domain of another size with as many cells
  // read the velocities on another spacing (a cavity's ke four times as large), where the grains'
  // box is the checkpoint's own.
  if (m.module_on("fluid"))
    for (const std::string& c : changed)
      if (c.starts_with("domain.lo =") || c.starts_with("domain.hi ="))
        throw IoError("checkpoint '" + path + "' holds a fluid on another domain: " + c +
                      " (its fields would be read on another grid)");
  if (differences) *differences = changed;
  State s = make_state(m);
  const auto n_fields = r.get<uint32_t>();
  if (n_fields < fid::kBuiltinCount || n_fields > 65535)
    throw IoError("checkpoint '" + path + "' holds " + std::to_string(n_fields) + " fields where this silt has " +
                  std::to_string(fid::kBuiltinCount) + " built-in ones (another silt version)");
  // The built-in fields in their order; then the modules' by name: one this silt does not have
  // must be empty (its module was off), and one the file does not have stays as a new state has
  // it (the checks below then require it where its module is on).
  for_each_field(s, [&](const FieldInfo& f, auto& v) {
    if (f.id >= fid::kBuiltinCount) return;
    const std::string stored_name = r.str();
    if (stored_name != f.name)
      throw IoError("checkpoint '" + path + "' was written by another silt version (field " + stored_name + " where " +
                    f.name + " is expected)");
    const auto elem = r.get<uint32_t>();
    const auto count = r.get<uint64_t>();
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
      if (elem != sizeof(v[0]) || count > buf.size() / sizeof(v[0]))
        throw IoError("checkpoint '" + path + "' is corrupt: bad field " + stored_name);
      v.resize(count);
      if (count) r.bytes(v.data(), count * sizeof(v[0]));
    } else {
      size_t size = 0;
      field_bytes(v, [&](const void*, size_t n) { size += n; });
      if (elem != size || count != 1) throw IoError("checkpoint '" + path + "' is corrupt: bad field " + stored_name);
      // The runs of field_bytes point into v: fill them in order.
      field_bytes(v, [&](const void* p, size_t n) { r.bytes(const_cast<void*>(p), n); });
      if (!bools_valid(v)) throw IoError("checkpoint '" + path + "' is corrupt: bad field " + stored_name);
    }
  });
  std::vector<uint8_t> loaded(s.module_fields.size(), 0);
  for (uint32_t k = fid::kBuiltinCount; k < n_fields; ++k) {
    const std::string name = r.str();
    const auto elem = r.get<uint32_t>();
    const auto count = r.get<uint64_t>();
    if (elem != sizeof(double) || count > buf.size() / sizeof(double))
      throw IoError("checkpoint '" + path + "' is corrupt: bad field " + name);
    const FieldInfo* f = find_field(name);
    if (!f || f->id < fid::kBuiltinCount) {
      if (count == 0) continue;
      throw IoError("checkpoint '" + path + "' holds field " + name + " of a module this silt does not have");
    }
    const size_t slot = f->id - fid::kBuiltinCount;
    if (loaded[slot]) throw IoError("checkpoint '" + path + "' is corrupt: field " + name + " twice");
    loaded[slot] = 1;
    std::vector<double>& v = s.module_fields[slot];
    v.resize(count);
    if (count) r.bytes(v.data(), count * sizeof(double));
  }
  // A module switched on or off since the file was written (`silt run --restore X --set
  // drag.viscosity=V` over a dry run's X was refused, where the shell's `restore X`, `set
  // drag.viscosity V` kept the state): the fields of a module now off are dropped, and those of one
  // now on that the file holds empty are made as a new state has them, as adopt_state does for a
  // state kept across a recompile. A grid's are left as they are (another grid, another system).
  fit_module_fields(m, s, FitFields::kEmptyPerGrain);
  if (const std::string bad = check_state(s, m); !bad.empty()) {
    // The same grains under other parameters (another fluid grid, a module switched on) give
    // fields of other lengths: say which parameters differ rather than call the file corrupt.
    if (changed.empty()) throw IoError("checkpoint '" + path + "' is corrupt: " + bad);
    std::string why = "checkpoint '" + path + "' does not fit this scene (" + bad + "); the scene differs from it in ";
    constexpr size_t kShown = 3;
    for (size_t k = 0; k < std::min(changed.size(), kShown); ++k) why += (k ? "; " : "") + changed[k];
    if (changed.size() > kShown) why += "; and " + std::to_string(changed.size() - kShown) + " more";
    throw IoError(why);
  }
  // Grains frozen since the scene's start (the shell's `freeze`) belong to the state: a caller that
  // freezes them too takes them, and nothing else.
  std::vector<uint8_t> more;
  int64_t freed = 0;
  if (const std::string diff = grains_difference(saved.fingerprint, s, m, more, freed); !diff.empty()) {
    const bool only_more = freed == 0 && std::find(more.begin(), more.end(), 1) != more.end();
    if (!frozen || !only_more)
      throw IoError(
          "checkpoint '" + path + "' was written for a different system: " + diff +
          (only_more ? " (frozen by `freeze`: the shell's restore and silt run --restore freeze them too)" : ""));
  }
  if (frozen) *frozen = std::move(more);
  // (a first step or an initial field given over a state past its start was a difference like
  // another, where the state goes on without it)
  if (differences && s.step > 0)
    for (std::string& d : *differences)
      if (const KeySpec* spec = find_key_spec(normalise_key(d.substr(0, d.find(" = ")))); spec && spec->initial)
        d += " (it makes the state at t = 0 only: this one, at step " + std::to_string(s.step) + ", goes on as it was)";
  return s;
}

}  // namespace silt
