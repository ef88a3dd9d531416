// Fast direct solver of (sigma - Lap_h) x = r on a uniform grid: the pressure Poisson equation of
// the projection (sigma = 0) and the implicit viscous Helmholtz equations (sigma = 1 / beta).
//
// Lap_h is the second-order 3- (5-, 7-) point Laplacian. Along each axis its eigenvectors are
// known for every boundary condition a face of the box can have, and FFTW's real-to-real
// transforms apply them in O(m log m) (Schumann & Sweet 1988; CaNS, Costa 2018):
//
//   axis kind   unknowns             symmetry of the data          transform    lambda_p h^2
//   periodic    m                    periodic                      complex n/2  2 - 2 cos(2 pi p / m)
//                                     (odd m: R2HC/HC2R)
//   cell NN     cell centres         even about -1/2 and m - 1/2  DCT-II/III   2 - 2 cos(pi p / m)
//                                     (even m: via complex m/2)
//   cell DD     (p = 0 on the faces)  odd about -1/2 and m - 1/2  DST-II/III   2 - 2 cos(pi (p + 1) / m)
//                                     (even m: via complex m/2)
//   cell ND / DN                     even / odd, odd / even        DCT-IV, DST-IV  2 - 2 cos(pi (p + 1/2) / m)
//   face DD     interior faces       odd about -1 and m            DST-I        2 - 2 cos(pi (p + 1) / (m + 1))
//                                     (odd m: via complex (m+1)/2)
//   face DN     faces 1 .. n         odd about -1, even about m - 1/2   (none: Thomas along it)
//
// Along the last axis, when it is not periodic, the equation of each horizontal mode is
// tridiagonal and solved directly (Thomas), which saves two transforms per solve; so along an
// axis of kind face DN (an outflow's normal velocity), which no FFTW transform diagonalises.
// Only one axis may be solved so. When every axis is transformed, the last one is transformed
// forward, its modes divided by their eigenvalues and transformed back block by block, in one
// pass over the data. In 3D (unless x or y is the Thomas axis) x and y go a group of z planes at
// a time, the group's lines along x then along y while it is in the cache (and back, y then x):
// a solve is three passes over the data instead of five. Measured on this machine (one periodic
// Poisson solve, best of 10 to 20): 256^3 in 5.7 to 6.0 ns a cell instead of 6.7 to 7.1 on one
// thread, 3.0 instead of 3.5 on two; 128^3 and below alone unchanged (their data stays in the
// last-level cache between passes).
//
// Transforms run on blocks of lines, each block of an axis with the same FFTW plan (chosen by
// FFTW_ESTIMATE, not by timing). A periodic line of even length goes through a complex transform
// of half its length, and so do the cosine and sine transforms of cell NN and DD lines of even
// length, their points reordered on the way in and out and their spectra rotated, and the sine
// transform of face DD lines of odd length (half_length_fft.hpp). Along x a block aligned as the
// planner's buffer is transformed where it lies, others are copied into aligned per-thread
// buffers; along y and z the lines of kBlock neighbouring x are copied into a buffer, read and
// written as whole rows: short lines (and those of the complex paths up to 1024 places)
// interleaved, so the transforms, the packing of the spectra and the division by the eigenvalues
// run across the block's lines, long ones transposed. Every
// line is transformed by the same code whatever thread runs it, so results are bitwise the same
// for any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace silt::fluid {

enum class AxisKind : uint8_t { kPeriodic, kCellNN, kCellDD, kCellND, kCellDN, kFaceDD, kFaceDN };

struct SolverAxis {
  int64_t m = 1;  // unknowns along the axis
  AxisKind kind = AxisKind::kPeriodic;
  double h = 1;
};

// The lines along x of a right-hand side or a solution where they lie in a field of another
// shape (a padded one): line (j, k) starts at base + j row + k plane.
struct SolveRows {
  double* base = nullptr;
  int64_t row = 0, plane = 0;
  // Line l of the solve's x-fastest numbering, m1 lines to a plane.
  double* line(int64_t l, int64_t m1) const { return base + (l % m1) * row + (l / m1) * plane; }
};
// Where a solve reads r (times scale) and writes x, when not in `data`: the first pass along x
// reads `in` and the last one writes `out` (data then holds the passes between), two passes over
// the grid fewer than copying into data and back.
struct SolveIo {
  const SolveRows* in = nullptr;
  double scale = 1;
  const SolveRows* out = nullptr;
};

// z planes [lo, hi) of a solve's grid; lo < 0: all of them, shared among the threads.
struct PlaneRange {
  int64_t lo = -1, hi = -1;
};

class FastSolver {
 public:
  static constexpr int kBlock = 32;   // lines per transform along y and z
  static constexpr int kLinesX = 64;  // along x (one allocation inside FFTW per call for some kinds)
  FastSolver(int dim, const std::array<SolverAxis, 3>& axes);
  ~FastSolver();
  FastSolver(const FastSolver&) = delete;
  FastSolver& operator=(const FastSolver&) = delete;

  // x = (sigma - Lap_h)^-1 r, in place on m0 * m1 * m2 values (x fastest); sigma >= 0. When the
  // operator is singular (sigma = 0, no Dirichlet condition), r must have zero sum and x is one
  // solution (another differs by a constant).
  void solve(double* data, double sigma) { solve(data, sigma, {}); }
  void solve(double* data, double sigma, const SolveIo& io);
  int64_t size() const { return m_[0] * m_[1] * m_[2]; }
  // Bytes of the per-thread buffers allocated so far.
  size_t bytes() const;
  // Eigenvalue of mode p along axis a, times h^2 (the table above).
  static double eigenvalue(AxisKind kind, int64_t p, int64_t m);
  // The frequency at position p of a periodic line of even length m in the packed order of its
  // real-to-complex transform (Re 0, Re m/2, Re 1, Im 1, Re 2, Im 2, ...).
  static int64_t packed_frequency(int64_t p, int64_t m);

 private:
  struct Plans;
  // (io: along x only, the first pass's input or the last one's output; planes: only the lines of
  // those z planes, along x or y, on the calling thread)
  void transform(double* data, int axis, bool forward, std::optional<double> divide_at = std::nullopt,
                 const SolveIo& io = {}, PlaneRange planes = {});
  // Along x then y forward (or y then x back), a group of z planes after the other: the group
  // stays in the cache between the two, one pass over the grid instead of two.
  void planes(double* data, bool forward, const SolveIo& io);
  static constexpr int64_t kPlaneGroupBytes = 1 << 20;
  // A buffer's block of lines into the eigenbasis (forward) and back.
  void through_modes(double* buf, int axis, bool forward);
  void divide_block(double* buf, int axis, int64_t i0, int64_t count, int64_t o, double sigma) const;
  void tridiagonal(double* data, double sigma);
  static constexpr int64_t kChunk = 64;  // modes per Thomas sweep
  // What stays in the first-level cache. Along y and z a block's lines are interleaved when the
  // block takes at most this (lines of up to 128 points), and so are the lines of a complex path
  // (the half-length transforms) of up to 8 times this (1024 places), in padded rows
  // (Plans::row); other lines are transposed. Lines one after the other are transformed and
  // finished a group of at most this at a time.
  static constexpr int64_t kCacheBlockBytes = 32 << 10;

  int dim_;
  std::array<int64_t, 3> m_{1, 1, 1};
  std::array<SolverAxis, 3> axes_;
  int64_t plane_group_ = 0;                    // z planes per group of planes(), 0: each axis in a pass of its own
  int tri_axis_ = -1;                          // the axis solved by the Thomas algorithm, -1: transforms on every axis
  std::array<std::vector<double>, 3> lambda_;  // eigenvalues / h^2 per axis
  double norm_ = 1;                            // product of the transforms' scale factors
  std::unique_ptr<Plans> plans_;
};

}  // namespace silt::fluid
