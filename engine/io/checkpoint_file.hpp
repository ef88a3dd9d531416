// The byte layout of checkpoint files (io/checkpoint.cpp has the whole layout): a writer and a
// bounds-checked reader of little-endian records, the system header, and a reader of a file's
// fields by name that needs no Model (to take grains from another scene's checkpoint).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "silt/errors.hpp"

namespace silt::ckpt {

constexpr char kMagic[8] = {'S', 'I', 'L', 'T', 'C', 'K', 'P', 'T'};
constexpr uint32_t kVersion = 5;

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    bytes(&v, sizeof v);
  }
  void bytes(const void* p, size_t n) {
    const size_t old = buf_.size();
    buf_.resize(old + n);
    if (n) std::memcpy(buf_.data() + old, p, n);
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
    if (n > b_.size() - pos_) throw IoError("checkpoint '" + path_ + "' is truncated");
    if (n) std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  // A count of items of `each` bytes that must fit in what is left of the file.
  uint32_t count(size_t each) {
    const auto n = get<uint32_t>();
    if (static_cast<uint64_t>(n) * each > b_.size() - pos_) throw IoError("checkpoint '" + path_ + "' is truncated");
    return n;
  }
  std::string str() {
    std::string x(count(1), '\0');
    bytes(x.data(), x.size());
    return x;
  }
  size_t left() const { return b_.size() - pos_; }

 private:
  const std::vector<char>& b_;
  std::string path_;
  size_t pos_ = 0;
};

// What a checkpoint belongs to: its grains (a fingerprint), dimension, periodicity and walls.
struct System {
  uint64_t fingerprint = 0;  // Model::scene_hash: grains, wall count, periodicity, dimension
  int32_t dim = 0;
  int64_t n = 0;
  std::array<uint8_t, 3> periodic{};
  std::vector<std::array<double, 6>> walls;  // point, unit normal
};
void put_system(Writer& w, const System& y);
System get_system(Reader& r);

// The file at `path`, whole, its magic, version and checksum checked; IoError with the reason.
std::vector<char> read_checked(const std::string& path);
// A reader past the magic and the version.
Reader body(const std::vector<char>& buf, const std::string& path);

// The fields of a checkpoint as records: name -> element size, count, bytes.
struct RawField {
  uint32_t elem = 0;
  uint64_t count = 0;
  std::vector<char> bytes;
};
struct RawCheckpoint {
  System system;
  std::string scene;
  std::map<std::string, RawField> fields;
  // A double array field, or IoError.
  std::vector<double> doubles(const std::string& name, const std::string& path) const;
  std::vector<int32_t> ints(const std::string& name, const std::string& path) const;
};
RawCheckpoint read_raw(const std::string& path);

}  // namespace silt::ckpt
