// Helpers for the large flat arrays of the State. Growing with little slack: std::vector::resize
// may double the capacity when it grows, which for the per-pair arrays of a dense bed is memory
// held for nothing; growing to exactly the new length reallocates at every neighbour build that
// lists a pair more, and fresh memory is fresh pages, each faulted in at its first touch (3 ms
// of a 12 ms build of the 17,600-grain chute on this virtual machine). A sixteenth of slack.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace silt {

// v.resize(n), allocating n and a sixteenth when the capacity is too small.
template <class T>
void resize_tight(std::vector<T>& v, size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 16);
  v.resize(n);
}

// v.assign(n, value), allocating as resize_tight does.
template <class T>
void assign_tight(std::vector<T>& v, size_t n, const T& value) {
  resize_tight(v, n);
  std::fill(v.begin(), v.end(), value);
}

// Whether any of v[0 .. n) has a bit set: a non-zero value, or a -0 (which a comparison with 0
// would not see). A pair whose force and spring have no bit set holds nothing to keep.
inline bool any_bit_set(const double* v, int n) {
  for (int k = 0; k < n; ++k)
    if (std::bit_cast<uint64_t>(v[k]) != 0) return true;
  return false;
}

}  // namespace silt
