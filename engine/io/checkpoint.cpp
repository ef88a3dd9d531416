// Checkpoint file layout (little-endian, version 3):
//   "SILTCKPT" | u32 version | u64 scene hash | i32 dim | i64 n | scalars | arrays | u64 FNV-1a
// Arrays follow the field list of State (name, element size, count, bytes), so a field added
// to SILT_STATE_ARRAYS is saved without touching this file. The file is written to PATH.tmp,
// flushed to disk and renamed over PATH: a crash during the write keeps the previous file.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/rng.hpp"
#include "silt/io.hpp"

namespace silt {
namespace {

constexpr char kMagic[8] = {'S', 'I', 'L', 'T', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 3;

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
  size_t pos() const { return pos_; }

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

}  // namespace

void write_checkpoint(const std::string& path, const Model& m, const State& s) {
  Writer w;
  w.bytes(kMagic, sizeof kMagic);
  w.put(kVersion);
  w.put(m.scene_hash);
  w.put(static_cast<int32_t>(m.dim));
  w.put(static_cast<int64_t>(s.n));
  auto put = [&w](const auto& v) { w.put(v); };
  scalars(put, s);
  for_each_array(s, [&](const char* name, const auto& v) {
    const uint32_t len = static_cast<uint32_t>(std::strlen(name));
    w.put(len);
    w.bytes(name, len);
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
      ::close(fd);
      ::unlink(tmp.c_str());
      throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(errno));
    }
    done += static_cast<size_t>(k);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    ::unlink(tmp.c_str());
    throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw IoError("cannot write checkpoint '" + path + "': " + std::strerror(errno));
}

State read_checkpoint(const std::string& path, const Model& m) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read checkpoint '" + path + "'");
  std::vector<char> buf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (buf.size() < sizeof kMagic + 12 || std::memcmp(buf.data(), kMagic, sizeof kMagic) != 0)
    throw IoError("'" + path + "' is not a silt checkpoint");
  uint64_t stored;
  std::memcpy(&stored, buf.data() + buf.size() - 8, 8);
  if (fnv1a(buf.data(), buf.size() - 8) != stored)
    throw IoError("checkpoint '" + path + "' is corrupt (checksum mismatch)");
  Reader r(buf, path);
  char magic[8];
  r.bytes(magic, 8);
  const auto version = r.get<uint32_t>();
  if (version != kVersion)
    throw IoError("checkpoint '" + path + "' has format version " + std::to_string(version) + "; this silt reads version " +
                  std::to_string(kVersion));
  if (r.get<uint64_t>() != m.scene_hash)
    throw IoError("checkpoint '" + path + "' was written for a different system (other grains, walls or periodicity)");
  State s = make_state(m);
  if (r.get<int32_t>() != m.dim || r.get<int64_t>() != s.n)
    throw IoError("checkpoint '" + path + "' does not match the scene's dimension or grain count");
  auto get = [&r](auto& v) { r.bytes(&v, sizeof v); };
  scalars(get, s);
  for_each_array(s, [&](const char* name, auto& v) {
    const auto len = r.get<uint32_t>();
    std::string stored_name(len, '\0');
    r.bytes(stored_name.data(), len);
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
