// Helpers for the large flat arrays of the State. Growing without slack: std::vector::resize
// may double the capacity when it grows, which for the per-pair arrays of a dense bed is memory
// held for nothing.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace silt {

// v.resize(n), allocating exactly n when the capacity is too small.
template <class T>
void resize_exact(std::vector<T>& v, size_t n) {
  if (n > v.capacity()) v.reserve(n);
  v.resize(n);
}

// Whether any of v[0 .. n) has a bit set: a non-zero value, or a -0 (which a comparison with 0
// would not see). A pair whose force and spring have no bit set holds nothing to keep.
inline bool any_bit_set(const double* v, int n) {
  for (int k = 0; k < n; ++k)
    if (std::bit_cast<uint64_t>(v[k]) != 0) return true;
  return false;
}

}  // namespace silt
