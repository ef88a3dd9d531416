#include "checkpoint_mutator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/rng.hpp"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace silt::fuzz {
namespace {

// Where things are in a checkpoint: the integers of the header and the records of the fields.
struct Number {
  size_t at, width;
};
struct Record {
  size_t start;  // the record's name length
  size_t elem_at, count_at, data_at, end;
  uint32_t elem;
  uint64_t count;
};
struct Layout {
  std::vector<Number> numbers;  // version, system, string lengths, counts
  size_t fields_count_at = 0;
  std::vector<Record> records;
  int64_t n = 0;  // grains, as the header says
};

class Walker {
 public:
  Walker(const uint8_t* d, size_t size) : d_(d), end_(size >= 8 ? size - 8 : 0) {}
  bool skip(size_t k) {
    if (k > end_ - pos_) return false;
    pos_ += k;
    return true;
  }
  template <class T>
  bool read(T& v, Layout* out) {
    if (sizeof v > end_ - pos_) return false;
    std::memcpy(&v, d_ + pos_, sizeof v);
    if (out) out->numbers.push_back({pos_, sizeof v});
    pos_ += sizeof v;
    return true;
  }
  bool str(Layout& out) {
    uint32_t k = 0;
    return read(k, &out) && skip(k);
  }
  size_t pos() const { return pos_; }

 private:
  const uint8_t* d_;
  size_t end_, pos_ = 0;
};

// As much of the layout as the bytes hold (a mutated file may stop anywhere).
Layout walk(const uint8_t* d, size_t size) {
  Layout L;
  Walker w(d, size);
  uint32_t u32 = 0;
  uint64_t u64 = 0;
  int32_t dim = 0;
  std::array<uint8_t, 3> periodic{};
  if (!w.skip(8) || !w.read(u32, &L) || !w.read(u64, &L) || !w.read(dim, &L) || !w.read(L.n, &L)) return L;
  for (uint8_t& p : periodic)
    if (!w.read(p, &L)) return L;
  uint32_t walls = 0;
  if (!w.read(walls, &L) || !w.skip(static_cast<size_t>(walls) * 48) || !w.str(L)) return L;
  uint32_t params = 0;
  if (!w.read(params, &L)) return L;
  for (uint32_t k = 0; k < params; ++k)
    if (!w.str(L) || !w.str(L)) return L;
  L.fields_count_at = w.pos();
  if (!w.read(u32, &L)) return L;
  for (uint32_t k = 0; k < u32; ++k) {
    Record r{};
    r.start = w.pos();
    if (!w.str(L)) return L;
    r.elem_at = w.pos();
    if (!w.read(r.elem, nullptr)) return L;
    r.count_at = w.pos();
    if (!w.read(r.count, nullptr)) return L;
    r.data_at = w.pos();
    if (r.elem == 0 || r.count > size / r.elem || !w.skip(r.elem * r.count)) return L;
    r.end = w.pos();
    L.records.push_back(r);
  }
  return L;
}

template <class T>
void store(uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof v);
}

// Values that the checks of a reader are about: limits, signs, the grain count and around it.
uint64_t special_integer(std::minstd_rand& rng, uint64_t old, int64_t n) {
  const uint64_t pick[] = {0,
                           1,
                           old + 1,
                           old - 1,
                           old * 2,
                           old / 2,
                           static_cast<uint64_t>(n),
                           static_cast<uint64_t>(n) + 1,
                           static_cast<uint64_t>(n) - 1,
                           std::numeric_limits<uint64_t>::max(),
                           static_cast<uint64_t>(std::numeric_limits<int32_t>::max()),
                           static_cast<uint64_t>(std::numeric_limits<int32_t>::min()),
                           uint64_t{1} << 31,
                           uint64_t{1} << 32,
                           uint64_t{1} << 62,
                           rng()};
  return pick[rng() % std::size(pick)];
}

double special_double(std::minstd_rand& rng, double old) {
  const double pick[] = {std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity(),
                         0.0,
                         -0.0,
                         -1.0,
                         1.0,
                         1e308,
                         -1e308,
                         std::numeric_limits<double>::denorm_min(),
                         1e30,
                         -old,
                         old * 1e10,
                         old * 2,
                         old + 1};
  return pick[rng() % std::size(pick)];
}

// A header integer set to a value near a limit.
bool mutate_number(uint8_t* d, const Layout& L, std::minstd_rand& rng) {
  if (L.numbers.empty()) return false;
  const Number& x = L.numbers[rng() % L.numbers.size()];
  uint64_t old = 0;
  std::memcpy(&old, d + x.at, x.width);
  const uint64_t v = special_integer(rng, old, L.n);
  std::memcpy(d + x.at, &v, x.width);  // little-endian: the low bytes
  return true;
}

// One element of a field's data: a special value of its kind, or another element's value.
bool mutate_element(uint8_t* d, const Layout& L, std::minstd_rand& rng) {
  std::vector<const Record*> some;
  for (const Record& r : L.records)
    if (r.count > 0) some.push_back(&r);
  if (some.empty()) return false;
  const Record& r = *some[rng() % some.size()];
  // Scalars are one element of their whole size (a Box member by member): take 8-byte words.
  const size_t width = r.elem <= 8 ? r.elem : (rng() % 2 ? 8 : 1);
  const size_t items = r.elem * r.count / width;
  uint8_t* p = d + r.data_at + (rng() % items) * width;
  if (rng() % 4 == 0) {  // a copy of another element: duplicate ids, pairs of another row
    std::memmove(p, d + r.data_at + (rng() % items) * width, width);
  } else if (width == 8 && rng() % 3) {
    double old;
    std::memcpy(&old, p, 8);
    store(p, special_double(rng, old));
  } else {
    uint64_t old = 0;
    std::memcpy(&old, p, width);
    const uint64_t v = special_integer(rng, old, L.n);
    std::memcpy(p, &v, width);
  }
  return true;
}

// Two elements of a field swapped: an order the reader may rely on (sorted rows, id order).
bool swap_elements(uint8_t* d, const Layout& L, std::minstd_rand& rng) {
  std::vector<const Record*> some;
  for (const Record& r : L.records)
    if (r.count > 1 && r.elem <= 8) some.push_back(&r);
  if (some.empty()) return false;
  const Record& r = *some[rng() % some.size()];
  uint8_t* a = d + r.data_at + (rng() % r.count) * r.elem;
  uint8_t* b = d + r.data_at + (rng() % r.count) * r.elem;
  std::array<uint8_t, 8> t{};
  std::memcpy(t.data(), a, r.elem);
  std::memmove(a, b, r.elem);
  std::memcpy(b, t.data(), r.elem);
  return true;
}

// Inserts `k` bytes at `at` (copies of the bytes before it when there are enough, else zeros) or
// removes -k bytes there; false when it does not fit in max_size.
bool resize_at(uint8_t* d, size_t& size, size_t max_size, size_t at, int64_t k) {
  if (k < 0) {
    const auto cut = static_cast<size_t>(-k);
    if (at + cut > size) return false;
    std::memmove(d + at, d + at + cut, size - at - cut);
    size -= cut;
    return true;
  }
  const auto add = static_cast<size_t>(k);
  if (size + add > max_size) return false;
  std::memmove(d + at + add, d + at, size - at);
  if (at >= add) std::memmove(d + at, d + at - add, add);
  else std::memset(d + at, 0, add);
  size += add;
  return true;
}

// A field array one element, one vector or one grain longer or shorter, its count kept in step
// with its bytes: the reader's length checks see a well-formed file.
bool resize_record(uint8_t* d, size_t& size, size_t max_size, const Layout& L, std::minstd_rand& rng) {
  if (L.records.empty()) return false;
  const Record& r = L.records[rng() % L.records.size()];
  const int64_t n = std::clamp<int64_t>(L.n, 0, 1 << 20);  // the header's, maybe mutated
  const int64_t steps[] = {1, -1, 2, -2, 3, -3, 4, -4, 6, -6, n, -n, -static_cast<int64_t>(r.count)};
  int64_t delta = steps[rng() % std::size(steps)];
  if (delta < 0 && static_cast<uint64_t>(-delta) > r.count) delta = -static_cast<int64_t>(r.count);
  if (delta == 0) return false;
  if (!resize_at(d, size, max_size, r.end, delta * static_cast<int64_t>(r.elem))) return false;
  store(d + r.count_at, static_cast<uint64_t>(static_cast<int64_t>(r.count) + delta));
  return true;
}

// A whole field record removed, repeated or moved, the field count left as it was or not.
bool move_record(uint8_t* d, size_t& size, size_t max_size, const Layout& L, std::minstd_rand& rng) {
  if (L.records.size() < 2) return false;
  const Record& r = L.records[rng() % L.records.size()];
  const size_t len = r.end - r.start;
  std::vector<uint8_t> copy(d + r.start, d + r.end);
  uint32_t fields = 0;
  std::memcpy(&fields, d + L.fields_count_at, 4);
  switch (rng() % 3) {
    case 0:  // removed
      if (!resize_at(d, size, max_size, r.start, -static_cast<int64_t>(len))) return false;
      if (rng() % 2) store(d + L.fields_count_at, fields - 1);
      return true;
    case 1:  // repeated
      if (!resize_at(d, size, max_size, r.end, static_cast<int64_t>(len))) return false;
      std::memcpy(d + r.end, copy.data(), len);
      if (rng() % 2) store(d + L.fields_count_at, fields + 1);
      return true;
    default: {  // moved to the start of another record
      const Record& to = L.records[rng() % L.records.size()];
      if (to.start == r.start) return false;
      resize_at(d, size, max_size, r.start, -static_cast<int64_t>(len));
      const size_t at = to.start < r.start ? to.start : to.start - len;
      resize_at(d, size, max_size, at, static_cast<int64_t>(len));
      std::memcpy(d + at, copy.data(), len);
      return true;
    }
  }
}

}  // namespace

void fix_checksum(uint8_t* data, size_t size) {
  if (size < 20) return;  // magic, version and the checksum itself
  store(data + size - 8, fnv1a(data, size - 8));
}

size_t mutate_checkpoint(uint8_t* data, size_t size, size_t max_size, unsigned int seed) {
  std::minstd_rand rng(seed);
  const Layout L = walk(data, size);
  bool done = false;
  switch (rng() % 8) {
    case 0: done = mutate_number(data, L, rng); break;
    case 1:
    case 2: done = mutate_element(data, L, rng); break;
    case 3: done = swap_elements(data, L, rng); break;
    case 4: done = resize_record(data, size, max_size, L, rng); break;
    case 5: done = move_record(data, size, max_size, L, rng); break;
    default: break;
  }
  if (!done) size = LLVMFuzzerMutate(data, size, max_size);
  if (rng() % 16) fix_checksum(data, size);  // now and then a wrong one: the checksum test stays covered
  return size;
}

}  // namespace silt::fuzz
