// Checkpoint file layout (little-endian, version 4):
//   "SILTCKPT" | u32 version | system | scene | scalars | arrays | u64 FNV-1a of all before it
//   system: u64 fingerprint (compile.cpp) | i32 dim | i64 n | u8 periodic[3] | u32 walls |
//           per wall f64 point[3], f64 normal[3]
//   scene:  str name | u32 count | count x (str key, str value)     str: u32 length, bytes
// The system decides whether a checkpoint can be restored: a state belongs to its grains, walls and
// periodicity, and is refused elsewhere with what differs. The scene part, every parameter's
// resolved value, only informs: a prepared packing is meant to be restored under other run
// parameters, and the values that differ (steered ones, say) are reported.
// Arrays follow the field list of State (name, element size, count, bytes), so a field added
// to SILT_STATE_ARRAYS is saved without touching this file. The file is written to PATH.tmp,
// flushed to disk, renamed over PATH and the directory flushed: a crash or a kill during the write
// keeps the previous file, and a crash after it keeps the new one.
#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/rng.hpp"
#include "core/text.hpp"
#include "silt/io.hpp"

namespace silt {
namespace {

constexpr char kMagic[8] = {'S', 'I', 'L', 'T', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 4;

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    bytes(&v, sizeof v);
  }
  void bytes(const void* p, size_t n) {
    const size_t old = buf_.size();
    buf_.resize(old + n);
    std::memcpy(buf_.data() + old, p, n);
  }
  void str(const std::string& x) {
    put(static_cast<uint32_t>(x.size()));
    bytes(x.data(), x.size());
  }
  std::vector<char> buf_;
};

class Reader {
 public:
  Reader(const std::vector<char>& b, const std::string& path) : b_(b), path_(path) {}
  template <class T>
  T get() {
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  void bytes(void* p, size_t n) {
    if (pos_ + n > b_.size()) throw IoError("checkpoint '" + path_ + "' is truncated");
    std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  // A count of items of `each` bytes that must fit in what is left of the file.
  uint32_t count(size_t each) {
    const auto n = get<uint32_t>();
    if (n * each > b_.size() - pos_) throw IoError("checkpoint '" + path_ + "' is truncated");
    return n;
  }
  std::string str() {
    std::string x(count(1), '\0');
    bytes(x.data(), x.size());
    return x;
  }

 private:
  const std::vector<char>& b_;
  std::string path_;
  size_t pos_ = 0;
};

template <class W, class S>
void scalars(W& io, S& s) {
  io(s.t);
  io(s.step);
  io(s.dt);
  io(s.box.lo);
  io(s.box.len);
  io(s.box.periodic);
  io(s.box_rate);
  io(s.box_stress);
  io(s.box.lees_edwards);
  io(s.box.le_offset);
  io(s.shear_rate);
  io(s.shear_stress);
  io(s.le_displacement);
  io(s.shear_strain);
  io(s.nbr_strain);
  io(s.nbr_valid);
  io(s.nbr_max_disp);
  io(s.nbr_builds);
}

// What a checkpoint belongs to: the refusal rule (layout above).
struct System {
  uint64_t fingerprint = 0;  // Model::scene_hash: grains, wall count, periodicity, dimension
  int32_t dim = 0;
  int64_t n = 0;
  std::array<uint8_t, 3> periodic{};
  std::vector<std::array<double, 6>> walls;  // point, unit normal
};

System system_of(const Model& m) {
  System y{m.scene_hash, m.dim, m.n_grains, {}, {}};
  for (int k = 0; k < 3; ++k) y.periodic[k] = m.box.periodic[k];
  for (const Wall& w : m.walls)
    y.walls.push_back({w.point[0], w.point[1], w.point[2], w.normal[0], w.normal[1], w.normal[2]});
  return y;
}

void put_system(Writer& w, const System& y) {
  w.put(y.fingerprint);
  w.put(y.dim);
  w.put(y.n);
  w.put(y.periodic);
  w.put(static_cast<uint32_t>(y.walls.size()));
  for (const auto& wall : y.walls) w.put(wall);
}

System get_system(Reader& r) {
  System y;
  y.fingerprint = r.get<uint64_t>();
  y.dim = r.get<int32_t>();
  y.n = r.get<int64_t>();
  y.periodic = r.get<std::array<uint8_t, 3>>();
  y.walls.resize(r.count(sizeof(y.walls[0])));
  for (auto& wall : y.walls) wall = r.get<std::array<double, 6>>();
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
  auto both = [](const std::string& a, const std::string& b) { return a + " in the checkpoint, " + b + " in the scene"; };
  if (saved.dim != now.dim) return both("dimension " + std::to_string(saved.dim), std::to_string(now.dim));
  if (saved.n != now.n) return both(std::to_string(saved.n) + " grains", std::to_string(now.n));
  if (saved.periodic != now.periodic)
    return both("periodic along " + axes(saved.periodic, saved.dim), axes(now.periodic, now.dim));
  if (saved.walls.size() != now.walls.size())
    return both(std::to_string(saved.walls.size()) + " wall(s)", std::to_string(now.walls.size()));
  for (size_t k = 0; k < now.walls.size(); ++k)
    if (saved.walls[k] != now.walls[k])
      return "wall " + std::to_string(k) + ": " + both(wall_text(saved.walls[k], saved.dim), wall_text(now.walls[k], now.dim));
  if (saved.fingerprint != now.fingerprint) return "the grains differ (sizes, masses, groups or frozen flags)";
  return "";
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

// The file at `path`, whole; IoError with the reason when it cannot be read.
std::vector<char> read_whole(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError("'" + path + "' is a directory, not a checkpoint");
  if (!std::filesystem::exists(path, ec)) throw IoError("cannot read checkpoint '" + path + "': no such file");
  try {
    std::ifstream in(path, std::ios::binary);
    if (in) return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  } catch (const std::exception&) {  // the stream library's words ("basic_filebuf::underflow error") help no one
  }
  throw IoError("cannot read checkpoint '" + path + "' (" + std::strerror(errno) + ")");
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
    for (int i = 0; i < d.group_count(group); ++i) add(group + "[" + std::to_string(i) + "]" + k.path.substr(br + 2), k);
  }
  return out;
}

void write_checkpoint(const std::string& path, const Model& m, const State& s) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError("cannot write checkpoint '" + path + "': it is a directory");
  Writer w;
  w.bytes(kMagic, sizeof kMagic);
  w.put(kVersion);
  put_system(w, system_of(m));
  w.str(m.scene_name);
  const auto params = scene_parameters(m.desc);
  w.put(static_cast<uint32_t>(params.size()));
  for (const auto& [key, value] : params) {
    w.str(key);
    w.str(value);
  }
  auto put = [&w](const auto& v) { w.put(v); };
  scalars(put, s);
  for_each_array(s, [&](const char* name, const auto& v) {
    w.str(name);
    w.put(static_cast<uint32_t>(sizeof(v[0])));
    w.put(static_cast<uint64_t>(v.size()));
    if (!v.empty()) w.bytes(v.data(), v.size() * sizeof(v[0]));
  });
  const uint64_t sum = fnv1a(w.buf_.data(), w.buf_.size());
  w.put(sum);
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
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

State read_checkpoint(const std::string& path, const Model& m, std::vector<std::string>* differences) {
  const std::vector<char> buf = read_whole(path);
  if (buf.size() < sizeof kMagic + 12 || std::memcmp(buf.data(), kMagic, sizeof kMagic) != 0)
    throw IoError("'" + path + "' is not a silt checkpoint");
  Reader r(buf, path);
  char magic[8];
  r.bytes(magic, 8);
  // The version first: another version may lay out (and check) the rest differently.
  const auto version = r.get<uint32_t>();
  if (version != kVersion)
    throw IoError("checkpoint '" + path + "' has format version " + std::to_string(version) + "; this silt reads version " +
                  std::to_string(kVersion) + " (write it again with the silt that can read it)");
  uint64_t stored;
  std::memcpy(&stored, buf.data() + buf.size() - 8, 8);
  if (fnv1a(buf.data(), buf.size() - 8) != stored)
    throw IoError("checkpoint '" + path + "' is corrupt (checksum mismatch)");
  if (const std::string diff = difference(get_system(r), system_of(m)); !diff.empty())
    throw IoError("checkpoint '" + path + "' was written for a different system: " + diff);
  r.str();  // the scene's name, also among the parameters (scene.name)
  std::vector<std::pair<std::string, std::string>> params(r.count(8));  // two lengths each
  for (auto& [key, value] : params) {
    key = r.str();
    value = r.str();
  }
  if (differences) *differences = parameter_differences(params, scene_parameters(m.desc));
  State s = make_state(m);
  auto get = [&r](auto& v) { r.bytes(&v, sizeof v); };
  scalars(get, s);
  for_each_array(s, [&](const char* name, auto& v) {
    const std::string stored_name = r.str();
    if (stored_name != name)
      throw IoError("checkpoint '" + path + "' was written by another silt version (field " + stored_name + " where " + name + " is expected)");
    const auto elem = r.get<uint32_t>();
    const auto count = r.get<uint64_t>();
    if (elem != sizeof(v[0]) || count > buf.size()) throw IoError("checkpoint '" + path + "': bad field " + stored_name);
    v.resize(count);
    if (count) r.bytes(v.data(), count * sizeof(v[0]));
  });
  return s;
}

}  // namespace silt
