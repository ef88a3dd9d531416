// Growing buffers without slack: std::vector::resize may double the capacity when it grows,
// which for the large per-pair arrays of a dense bed is memory held for nothing.
#pragma once

#include <cstddef>
#include <vector>

namespace silt {

// v.resize(n), allocating exactly n when the capacity is too small.
template <class T>
void resize_exact(std::vector<T>& v, size_t n) {
  if (n > v.capacity()) v.reserve(n);
  v.resize(n);
}

}  // namespace silt
