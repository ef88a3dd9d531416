#include "io/checkpoint_file.hpp"

#include <cerrno>
#include <fstream>

#include "core/rng.hpp"
#include "silt/input_files.hpp"

namespace silt::ckpt {

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

std::vector<char> read_checked(const std::string& path) {
  check_input_file(path, "checkpoint", max_checkpoint_bytes());
  std::vector<char> buf;
  bool read = false;
  try {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      buf.assign((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      read = true;
    }
  } catch (const std::exception&) {  // the stream library's words ("basic_filebuf::underflow error") help no one
  }
  if (!read) throw IoError("cannot read checkpoint '" + path + "' (" + std::strerror(errno) + ")");
  if (buf.size() < sizeof kMagic + 12 || std::memcmp(buf.data(), kMagic, sizeof kMagic) != 0)
    throw IoError("'" + path + "' is not a silt checkpoint");
  // The version first: another version may lay out (and check) the rest differently.
  uint32_t version;
  std::memcpy(&version, buf.data() + sizeof kMagic, sizeof version);
  if (version != kVersion)
    throw IoError("checkpoint '" + path + "' has format version " + std::to_string(version) +
                  "; this silt reads version " + std::to_string(kVersion) +
                  " (write it again with the silt that can read it)");
  uint64_t stored;
  std::memcpy(&stored, buf.data() + buf.size() - 8, 8);
  if (fnv1a(buf.data(), buf.size() - 8) != stored)
    throw IoError("checkpoint '" + path + "' is corrupt (checksum mismatch)");
  return buf;
}

Reader body(const std::vector<char>& buf, const std::string& path) {
  Reader r(buf, path);
  char head[sizeof kMagic + sizeof kVersion];
  r.bytes(head, sizeof head);
  return r;
}

RawCheckpoint read_raw(const std::string& path) {
  const std::vector<char> buf = read_checked(path);
  Reader r = body(buf, path);
  RawCheckpoint c;
  c.system = get_system(r);
  c.scene = r.str();
  const uint32_t params = r.count(8);
  for (uint32_t k = 0; k < 2 * params; ++k) r.str();
  const auto n = r.get<uint32_t>();
  for (uint32_t k = 0; k < n; ++k) {
    const std::string name = r.str();
    RawField f;
    f.elem = r.get<uint32_t>();
    f.count = r.get<uint64_t>();
    if (f.elem == 0 || f.count > r.left() / f.elem)
      throw IoError("checkpoint '" + path + "' is corrupt: bad field " + name);
    f.bytes.resize(f.elem * f.count);
    r.bytes(f.bytes.data(), f.bytes.size());
    c.fields[name] = std::move(f);
  }
  return c;
}

namespace {
template <class T>
std::vector<T> array_of(const RawCheckpoint& c, const std::string& name, const std::string& path) {
  auto it = c.fields.find(name);
  if (it == c.fields.end() || it->second.elem != sizeof(T))
    throw IoError("checkpoint '" + path + "' has no field " + name + " of the expected kind");
  std::vector<T> v(it->second.count);
  if (!v.empty()) std::memcpy(v.data(), it->second.bytes.data(), v.size() * sizeof(T));
  return v;
}
}  // namespace

std::vector<double> RawCheckpoint::doubles(const std::string& name, const std::string& path) const {
  return array_of<double>(*this, name, path);
}
std::vector<int32_t> RawCheckpoint::ints(const std::string& name, const std::string& path) const {
  return array_of<int32_t>(*this, name, path);
}

}  // namespace silt::ckpt
