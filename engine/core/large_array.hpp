// Arrays of many megabytes that a step sweeps plane by plane (the fluid's fields): allocated on
// 2 MiB boundaries and advised to the kernel as huge-page memory (madvise MADV_HUGEPAGE, which
// Debian's default transparent_hugepage = madvise honours and nothing else asks for). A stencil or
// a transform along z reads rows a plane apart, each on its own 4 KiB page, more pages than the
// TLB maps; on 2 MiB pages a 128^3 grid's field is eight of them. Arrays under 16 MiB are
// allocated as usual (the last huge page of an array is held whole: at most 1/8 more memory). The
// values are the same either way: only where they lie changes.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace silt {

template <class T>
struct LargeArrayAllocator {
  using value_type = T;
  static constexpr size_t kHuge = size_t{2} << 20;
  LargeArrayAllocator() = default;
  template <class U>
  LargeArrayAllocator(const LargeArrayAllocator<U>&) {}  // NOLINT(google-explicit-constructor)
  static bool huge(size_t n) { return n * sizeof(T) >= 8 * kHuge; }
  T* allocate(size_t n) {
    if (!huge(n)) return std::allocator<T>().allocate(n);
    const size_t bytes = (n * sizeof(T) + kHuge - 1) / kHuge * kHuge;
    void* p = std::aligned_alloc(kHuge, bytes);
    if (!p) throw std::bad_alloc();
    madvise(p, bytes, MADV_HUGEPAGE);  // advice: where the kernel cannot, 4 KiB pages as before
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    if (!huge(n)) return std::allocator<T>().deallocate(p, n);
    std::free(p);
  }
  template <class U>
  bool operator==(const LargeArrayAllocator<U>&) const {
    return true;
  }
};

template <class T>
using LargeArray = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace silt
