// The fast solver's plans and buffers, shared by its two sources: fast_solver.cpp (the axes, the
// eigenvalues, the division and the Thomas sweeps) and fast_solver_lines.cpp (the lines of a
// block into the buffers, through the transforms and back).
#pragma once

#include <fftw3.h>
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <vector>

#include "fluid/fast_solver.hpp"
#include "fluid/half_length_fft.hpp"

namespace silt::fluid {

// FFTW's planner is not thread-safe (its execution is): plans are made under one lock.
inline std::mutex& planner_lock() {
  static std::mutex m;
  return m;
}

struct FftwFree {
  void operator()(double* p) const { fftw_free(p); }
};
using Buffer = std::unique_ptr<double, FftwFree>;
inline Buffer make_buffer(int64_t n) {
  auto* p = static_cast<double*>(fftw_malloc(sizeof(double) * static_cast<size_t>(std::max<int64_t>(n, 1))));
  if (!p) throw std::bad_alloc();
  return Buffer(p);
}

// How the lines of an axis are transformed.
enum class LinePath : uint8_t {
  kRealToReal,  // FFTW's real-to-real pair
  kPeriodic,    // the half-length complex transform (periodic, even length)
  kCosine,      // and the cosine transform from it (cell NN, even length)
  kSine,        // and the sine transform (cell DD, even length)
  kFaceSine,    // and the sine transform of interior faces (face DD, odd length)
};

inline bool half_length(LinePath p) { return p != LinePath::kRealToReal; }
inline bool cosine_like(LinePath p) { return p == LinePath::kCosine || p == LinePath::kSine; }

// Where the points of a line of n points sit among the places of its path in the buffer. The
// cosine and sine paths reorder them where they are points (going in forward, coming out
// backward): place r holds point cosine_source(r, n), negated for the sine when that point is
// odd. The face sine path, its own inverse, shifts them by one place going in either way (place 0
// is zero, place r holds point r - 1) and takes the first n places out.
inline bool reorders_in(LinePath p, bool forward) { return cosine_like(p) ? forward : p == LinePath::kFaceSine; }
inline bool reorders_out(LinePath p, bool forward) { return cosine_like(p) && !forward; }
// The point at place r (-1: the place is zero) and its sign, when the path reorders.
inline int64_t place_point(LinePath p, int64_t r, int64_t n) {
  return p == LinePath::kFaceSine ? r - 1 : cosine_source(r, n);
}
inline double place_sign(LinePath p, int64_t r, int64_t n) {
  return p == LinePath::kSine && cosine_source(r, n) % 2 == 1 ? -1.0 : 1.0;
}

// Per axis, the forward and backward plans of one block of lines (kLinesX along x, kBlock along y
// and z), in place on an aligned buffer, and how the lines sit there.
struct FastSolver::Plans {
  using Path = LinePath;
  std::array<fftw_plan, 3> fwd{}, bwd{};
  std::array<Path, 3> path{};
  std::array<std::vector<double>, 3> twiddles;           // of the half-length axes (half_length_fft.hpp)
  std::array<std::vector<double>, 3> cosines;            // of the cosine and sine axes
  std::array<std::vector<double>, 3> sines;              // of the face sine axes
  std::array<int64_t, 3> slots{1, 1, 1};                 // places of a line in the buffer: m, or m + 1 (face sine)
  std::array<bool, 3> interleaved{false, false, false};  // a block's lines interleaved (y, z; short lines)
  // Between the rows of an interleaved block (a place of each line, or a complex value of each
  // packed line): kBlock or 2 kBlock values, and 8 more when the block would not stay in the
  // first-level cache. Rows of 2^k values put a transform's points on a few cache sets, which
  // then evict one another: FFTW's 128-point complex transform of 32 such lines runs 1.5 times
  // as fast in rows of 72 values as in rows of 64 (0.79 against 1.21 ns a point, this machine).
  std::array<int64_t, 3> row{1, 1, 1};
  std::array<int64_t, 3> group{1, 1, 1};  // lines per complex transform of a packed axis not interleaved
  // Between the lines of a block not interleaved: m along x (a block in place), along y and z m
  // rounded up to 8 and 8 more, so that a block's lines neither start on the same cache set
  // (lines of 2^k points would) nor lose the 64-byte alignment of the buffer.
  std::array<int64_t, 3> stride{1, 1, 1};
  int64_t buffer_size = 0;
  tbb::enumerable_thread_specific<Buffer> buffers;
  tbb::enumerable_thread_specific<std::vector<double>> scratch;
  ~Plans() {
    std::lock_guard<std::mutex> lock(planner_lock());
    for (int a = 0; a < 3; ++a) {
      if (fwd[a]) fftw_destroy_plan(fwd[a]);
      if (bwd[a]) fftw_destroy_plan(bwd[a]);
    }
  }
  double* buffer() {
    Buffer& b = buffers.local();
    if (!b) b = make_buffer(buffer_size);
    return b.get();
  }
  // Per-thread scratch of n values (the Thomas sweep's upper diagonals, a block's eigenvalues).
  double* scratch_of(int64_t n) {
    std::vector<double>& v = scratch.local();
    if (static_cast<int64_t>(v.size()) < n) v.resize(static_cast<size_t>(n));
    return v.data();
  }
};

}  // namespace silt::fluid
