#include "fluid/fast_solver.hpp"

#include <fftw3.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "core/parallel.hpp"
#include "core/simd_level.hpp"
#include "fluid/fast_solver_plans.hpp"
#include "fluid/half_length_fft.hpp"
#include "fluid/sweep_for.hpp"

namespace silt::fluid {
namespace {

// The transform pair of an axis kind (forward: into the eigenbasis), and its scale factor.
void kinds_of(AxisKind k, fftw_r2r_kind& fwd, fftw_r2r_kind& bwd) {
  switch (k) {
    case AxisKind::kPeriodic: fwd = FFTW_R2HC, bwd = FFTW_HC2R; return;
    case AxisKind::kCellNN: fwd = FFTW_REDFT10, bwd = FFTW_REDFT01; return;
    case AxisKind::kCellDD: fwd = FFTW_RODFT10, bwd = FFTW_RODFT01; return;
    case AxisKind::kCellND: fwd = bwd = FFTW_REDFT11; return;
    case AxisKind::kCellDN: fwd = bwd = FFTW_RODFT11; return;
    case AxisKind::kFaceDD: fwd = bwd = FFTW_RODFT00; return;
    case AxisKind::kFaceDN: fwd = bwd = FFTW_R2HC; return;  // not a transform: solved by Thomas
  }
}
double scale_of(AxisKind k, int64_t m) {
  if (k == AxisKind::kPeriodic) return static_cast<double>(m);
  if (k == AxisKind::kFaceDD) return 2.0 * static_cast<double>(m + 1);
  return 2.0 * static_cast<double>(m);
}

// Tridiagonal end rows of -h^2 d2/dx2 along the last axis: the diagonal entry of the first and
// the last unknown (interior rows have 2): a Neumann end 1, a Dirichlet face half a cell away 3,
// a Dirichlet point one cell away 2.
std::array<double, 2> end_diagonals(AxisKind k) {
  switch (k) {
    case AxisKind::kCellNN: return {1, 1};
    case AxisKind::kCellDD: return {3, 3};
    case AxisKind::kCellND: return {1, 3};
    case AxisKind::kCellDN: return {3, 1};
    case AxisKind::kFaceDD: return {2, 2};
    case AxisKind::kFaceDN: return {2, 1};
    default: return {2, 2};
  }
}

}  // namespace

int64_t FastSolver::packed_frequency(int64_t p, int64_t m) {
  if (p == 0) return 0;
  return p == 1 ? m / 2 : p / 2;
}

double FastSolver::eigenvalue(AxisKind kind, int64_t p, int64_t m) {
  const double pi = std::numbers::pi, q = static_cast<double>(p), n = static_cast<double>(m);
  switch (kind) {
    case AxisKind::kPeriodic: {
      // Halfcomplex order: entry p holds the real part of frequency p (p <= m/2) or the imaginary
      // part of frequency m - p; both have the eigenvalue of frequency p.
      return 2 - 2 * std::cos(2 * pi * q / n);
    }
    case AxisKind::kCellNN: return 2 - 2 * std::cos(pi * q / n);
    case AxisKind::kCellDD: return 2 - 2 * std::cos(pi * (q + 1) / n);
    case AxisKind::kFaceDD: return 2 - 2 * std::cos(pi * (q + 1) / (n + 1));
    default: return 2 - 2 * std::cos(pi * (q + 0.5) / n);
  }
}

FastSolver::FastSolver(int dim, const std::array<SolverAxis, 3>& axes)
    : dim_(dim), axes_(axes), plans_(std::make_unique<Plans>()) {
  for (int a = 0; a < 3; ++a) m_[a] = a < dim ? axes[a].m : 1;
  // The Thomas algorithm along the last axis when it is not periodic, or along an axis whose kind
  // no FFTW transform has (face DN: odd about -1, even about m - 1/2).
  tri_axis_ = axes[dim - 1].kind == AxisKind::kPeriodic ? -1 : dim - 1;
  for (int a = 0; a < dim; ++a)
    if (axes[a].kind == AxisKind::kFaceDN) tri_axis_ = a;
  // A periodic axis of even length is transformed by a complex transform of half its length
  // (half_length_fft.hpp), whose vectorised codelets run two to three times as fast as FFTW's
  // real-to-complex and halfcomplex ones, in the packed order below (packed_frequency); so are
  // the cosine and sine transforms of cells between Neumann or Dirichlet ends (cell NN, DD) of
  // even length, reordered and rotated (cosine_mode). Odd lengths and the other kinds keep
  // FFTW's real-to-real pairs.
  using Path = Plans::Path;
  for (int a = 0; a < dim; ++a) {
    const bool even = m_[a] % 2 == 0 && a != tri_axis_;
    Path& path = plans_->path[a];
    if (even && axes[a].kind == AxisKind::kPeriodic) path = Path::kPeriodic;
    if (even && axes[a].kind == AxisKind::kCellNN) path = Path::kCosine;
    if (even && axes[a].kind == AxisKind::kCellDD) path = Path::kSine;
    if (m_[a] % 2 == 1 && a != tri_axis_ && axes[a].kind == AxisKind::kFaceDD) path = Path::kFaceSine;
    const int64_t n = plans_->slots[a] = path == Path::kFaceSine ? m_[a] + 1 : m_[a];
    if (half_length(path)) plans_->twiddles[a] = half_length_twiddles(n);
    if (cosine_like(path)) plans_->cosines[a] = cosine_twiddles(n);
    if (path == Path::kFaceSine) plans_->sines[a] = face_sine_table(n);
    // Interleaved when the block stays in the first-level cache; so are the lines of a complex
    // path of up to 8 times that (1024 places), in padded rows: gathered and scattered as whole
    // rows, where a transposed block's values go one to a line. Measured on this machine (one
    // periodic Poisson solve, one thread): 256^3 in 6.8 ns a cell instead of 8.6 to 9.1 (two
    // threads 3.5 instead of 4.5), 1024^2 and 512^2 5 to 10 % faster; 128^3 and below unchanged.
    const int64_t block_bytes = n * kBlock * static_cast<int64_t>(sizeof(double));
    const bool fits = block_bytes <= kCacheBlockBytes;
    plans_->interleaved[a] = a > 0 && (fits || (half_length(path) && block_bytes <= 8 * kCacheBlockBytes));
    if (plans_->interleaved[a]) plans_->row[a] = (half_length(path) ? 2 * kBlock : kBlock) + (fits ? 0 : 8);
    // Lines one after the other: transformed and packed a group at a time, the group in the
    // first-level cache between the two; a group starts 64 bytes after the one before it (the
    // alignment the plan was made for), or the block is one group.
    const int64_t lines = a == 0 ? kLinesX : kBlock;
    plans_->stride[a] = a == 0 || plans_->interleaved[a] ? n : (n + 7) / 8 * 8 + 8;
    int64_t g = lines;
    while (g > 1 && g * n * static_cast<int64_t>(sizeof(double)) > kCacheBlockBytes) g /= 2;
    plans_->group[a] = (g * plans_->stride[a]) % 8 == 0 ? g : lines;
  }
  // x and y a group of z planes at a time: the fewest planes whose lines along x fill whole blocks
  // of kLinesX, when x and y are transformed (neither is the Thomas axis), the group takes at
  // most kPlaneGroupBytes and the box holds at least 4 groups (fewer keep the threads on the
  // lines of each axis; the lines see the same operations either way).
  if (dim == 3 && tri_axis_ != 0 && tri_axis_ != 1) {
    const int64_t g = kLinesX / std::gcd(int64_t{kLinesX}, m_[1]);
    if (g * m_[0] * m_[1] * static_cast<int64_t>(sizeof(double)) <= kPlaneGroupBytes && m_[2] >= 4 * g)
      plane_group_ = g;
  }
  int64_t largest = plans_->slots[0] * kLinesX;  // block
  for (int a = 0; a < dim; ++a) {
    lambda_[a].resize(m_[a]);
    const double ih2 = 1 / (axes[a].h * axes[a].h);
    for (int64_t p = 0; p < m_[a]; ++p) {
      int64_t q = p;  // the mode at place p
      if (plans_->path[a] == Path::kPeriodic) q = packed_frequency(p, m_[a]);
      if (plans_->path[a] == Path::kCosine) q = cosine_mode(p, m_[a]);
      if (plans_->path[a] == Path::kSine) q = m_[a] - 1 - cosine_mode(p, m_[a]);
      lambda_[a][p] = eigenvalue(axes[a].kind, q, m_[a]) * ih2;
    }
    const int64_t rows = half_length(plans_->path[a]) ? plans_->slots[a] / 2 : plans_->slots[a];
    largest = std::max(largest, plans_->interleaved[a] ? rows * plans_->row[a] : plans_->stride[a] * kBlock);
  }
  plans_->buffer_size = largest;
  Buffer probe = make_buffer(plans_->buffer_size);
  std::lock_guard<std::mutex> lock(planner_lock());
  for (int a = 0; a < dim; ++a) {
    if (a == tri_axis_) continue;
    // The lines one after the other, or interleaved (point j of line b at j row + b; complex
    // value k of the packed lines at k row + 2 b).
    const int n = static_cast<int>(plans_->slots[a]), lines = a == 0 ? kLinesX : kBlock;
    const bool il = plans_->interleaved[a];
    const int packed_lines = il ? lines : static_cast<int>(plans_->group[a]);
    // between points (in complex values for packed lines), between lines
    const int row = static_cast<int>(plans_->row[a]);
    const int step = il ? (half_length(plans_->path[a]) ? row / 2 : row) : 1;
    const int dist = il ? 1 : static_cast<int>(plans_->stride[a]);
    // FFTW_ESTIMATE: the plan from heuristics, never from timings, so every run makes the same one.
    if (half_length(plans_->path[a])) {
      // In place: each line of n reals as n / 2 complex values.
      auto* c = reinterpret_cast<fftw_complex*>(probe.get());
      const int h = n / 2, cd = il ? 1 : dist / 2;
      plans_->fwd[a] = fftw_plan_many_dft(1, &h, packed_lines, c, nullptr, step, cd, c, nullptr, step, cd, FFTW_FORWARD,
                                          FFTW_ESTIMATE);
      plans_->bwd[a] = fftw_plan_many_dft(1, &h, packed_lines, c, nullptr, step, cd, c, nullptr, step, cd,
                                          FFTW_BACKWARD, FFTW_ESTIMATE);
    } else {
      fftw_r2r_kind f, b;
      kinds_of(axes[a].kind, f, b);
      double* d = probe.get();
      plans_->fwd[a] =
          fftw_plan_many_r2r(1, &n, lines, d, nullptr, step, dist, d, nullptr, step, dist, &f, FFTW_ESTIMATE);
      plans_->bwd[a] =
          fftw_plan_many_r2r(1, &n, lines, d, nullptr, step, dist, d, nullptr, step, dist, &b, FFTW_ESTIMATE);
    }
    if (!plans_->fwd[a] || !plans_->bwd[a]) throw std::runtime_error("FFTW could not plan a transform");
    norm_ *= scale_of(axes[a].kind, m_[a]);
  }
}

FastSolver::~FastSolver() = default;

size_t FastSolver::bytes() const {
  size_t b = 0;
  for (const Buffer& buf : plans_->buffers)
    if (buf) b += static_cast<size_t>(plans_->buffer_size) * sizeof(double);
  for (const std::vector<double>& v : plans_->scratch) b += v.capacity() * sizeof(double);
  return b;
}

// Every axis transformed: divide each mode of a gathered block (lines along `axis`, the last one;
// x = i0 + b for b < count, the other index o) by its eigenvalue and the transforms' scale.
void FastSolver::divide_block(double* buf, int axis, int64_t i0, int64_t count, int64_t o, double sigma) const {
  const double inv_norm = 1 / norm_;
  const int64_t n = m_[axis];
  // sigma plus the eigenvalues along y and z, per point j of the lines.
  double* base = plans_->scratch_of(n);
  for (int64_t j = 0; j < n; ++j) {
    const int64_t y = axis == 2 ? o : j, z = axis == 2 ? j : o;
    base[j] = sigma + lambda_[1][y] + (dim_ == 3 ? lambda_[2][z] : 0.0);
  }
  // Position p of line b: interleaved, at (p / 2) row + 2 b + p % 2 when packed (a complex value
  // per two positions), at p row + b otherwise; transposed, at b stride + p.
  const bool packed = half_length(plans_->path[axis]);
  const double* lx = lambda_[0].data() + i0;
  auto divide = [inv_norm](double& v, double l) {
    const double q = v * inv_norm / (l > 0 ? l : 1.0);
    v = l > 0 ? q : 0.0;  // the singular mode: zero mean
  };
  run_simd([&] {
    if (!plans_->interleaved[axis]) {
      for (int64_t b = 0; b < count; ++b) {
        double* line = buf + b * plans_->stride[axis];
        SILT_IVDEP
        for (int64_t p = 0; p < n; ++p) divide(line[p], base[p] + lx[b]);
      }
      return;
    }
    if (packed) {
      for (int64_t p = 0; p < n; p += 2) {
        double* row = buf + (p / 2) * plans_->row[axis];
        const double s0 = base[p], s1 = base[p + 1];
        SILT_IVDEP
        for (int64_t b = 0; b < count; ++b) {
          divide(row[2 * b], s0 + lx[b]);
          divide(row[2 * b + 1], s1 + lx[b]);
        }
      }
      return;
    }
    for (int64_t p = 0; p < n; ++p) {
      double* row = buf + p * plans_->row[axis];
      SILT_IVDEP
      for (int64_t b = 0; b < count; ++b) divide(row[b], base[p] + lx[b]);
    }
  });
}

// The Thomas algorithm along axis t, for every mode q of the other axes: row k of mode q is
// -x_{k-1} + d_k x_k - x_{k+1} = h^2 r_k with d_k = 2 + h^2 (sigma + lambda_q) (ends as
// end_diagonals). A singular mode (every other axis at its zero mode, Neumann ends, sigma = 0)
// has x_0 = 0 imposed: the solution of the compatible system with that gauge. Values are stored
// as the data: (i_in, k, o) at i_in + inner (k + m_t o), i_in over the axes below t, o above it.
// The pivots are computed as the forward sweep goes (sigma changes from one Runge-Kutta substep
// to the next): chunks of kChunk neighbouring modes of one o, so that the sweeps over k read and
// write contiguous runs of i_in, with the modified upper diagonals of the chunk in a per-thread
// scratch array for the backward sweep.
void FastSolver::tridiagonal(double* data, double sigma) {
  const int t = tri_axis_;
  const int64_t nk = m_[t], inner = t == 0 ? 1 : (t == 1 ? m_[0] : m_[0] * m_[1]), outer = size() / (inner * nk);
  const double h2 = axes_[t].h * axes_[t].h, scale = h2 / norm_;
  const auto ends = end_diagonals(axes_[t].kind);
  const bool neumann_both = ends[0] == 1 && ends[1] == 1;
  const int64_t chunks = (inner + kChunk - 1) / kChunk;
  sweep_for(m_[0] * m_[1] * m_[2], outer * chunks, 1, [&](int64_t c0, int64_t c1) {
    double* up_diag = plans_->scratch_of(kChunk * nk);
    for (int64_t c = c0; c < c1; ++c) {
      const int64_t o = c / chunks, i0 = (c % chunks) * kChunk, n = std::min(inner, i0 + kChunk) - i0;
      const int64_t base = inner * nk * o + i0;
      // sigma plus the eigenvalues of the other axes, per mode of the chunk.
      std::array<double, kChunk> lq;
      for (int64_t l = 0; l < n; ++l) {
        std::array<int64_t, 3> idx{0, 0, 0};
        int64_t rest = i0 + l;
        for (int a = 0; a < t; ++a) {
          idx[a] = rest % m_[a];
          rest /= m_[a];
        }
        rest = o;
        for (int a = t + 1; a < dim_; ++a) {
          idx[a] = rest % m_[a];
          rest /= m_[a];
        }
        lq[l] = sigma;
        for (int a = 0; a < dim_; ++a)
          if (a != t) lq[l] += lambda_[a][idx[a]];
      }
      for (int64_t k = 0; k < nk; ++k) {
        double* x = data + base + inner * k;
        const double* xp = x - inner;
        double* cu = up_diag + kChunk * k;
        const double* cp = k > 0 ? cu - kChunk : cu;  // the level above (read from k = 1)
        const double end = k == 0 ? ends[0] : (k == nk - 1 ? ends[1] : 2.0);
        const double up0 = k < nk - 1 ? -1.0 : 0.0;
        run_simd([&] {
          for (int64_t l = 0; l < n; ++l) {
            const double d = nk == 1 ? ends[0] + ends[1] - 2 + h2 * lq[l] : end + h2 * lq[l];
            double pivot = d + (k > 0 ? cp[l] : 0.0), up = up0;
            const bool gauge = k == 0 && !(lq[l] > 0) && neumann_both;  // x_0 = 0
            if (gauge) pivot = 1, up = 0;
            // up is -1 or 0: up / pivot is up times 1 / pivot, to the bit.
            const double inv = 1 / pivot;
            cu[l] = up * inv;
            double r = x[l] * scale;
            if (k == 0 && neumann_both && cu[l] == 0 && nk > 1) r = 0;  // the gauge row
            x[l] = k == 0 ? r * inv : (r + xp[l]) * inv;
          }
        });
      }
      for (int64_t k = nk - 2; k >= 0; --k) {
        double* x = data + base + inner * k;
        const double* xn = x + inner;
        const double* cu = up_diag + kChunk * k;
        run_simd([&] {
          for (int64_t l = 0; l < n; ++l) x[l] -= cu[l] * xn[l];
        });
      }
    }
  });
}

void FastSolver::planes(double* data, bool forward, const SolveIo& io) {
  const int64_t g = plane_group_, groups = (m_[2] + g - 1) / g;
  sweep_for(size(), groups, 1, [&](int64_t g0, int64_t g1) {
    for (int64_t q = g0; q < g1; ++q)
      for (int a : forward ? std::array<int, 2>{0, 1} : std::array<int, 2>{1, 0})
        transform(data, a, forward, std::nullopt, a == 0 ? io : SolveIo{}, {q * g, std::min(m_[2], (q + 1) * g)});
  });
}

void FastSolver::solve(double* data, double sigma, const SolveIo& io) {
  const SolveIo in{io.in, io.scale, nullptr}, out{nullptr, 1, io.out};
  if (tri_axis_ == 0 && (io.in || io.out)) {
    // Along x the Thomas sweeps: the lines copied in and out.
    const int64_t n = m_[0], lines = size() / n;
    if (io.in)
      sweep_for(size(), lines, 8, [&](int64_t l0, int64_t l1) {
        for (int64_t l = l0; l < l1; ++l) {
          const double* from = io.in->line(l, m_[1]);
          for (int64_t i = 0; i < n; ++i) data[l * n + i] = from[i] * io.scale;
        }
      });
    solve(data, sigma, {});
    if (io.out)
      sweep_for(size(), lines, 8, [&](int64_t l0, int64_t l1) {
        for (int64_t l = l0; l < l1; ++l) std::memcpy(io.out->line(l, m_[1]), data + l * n, sizeof(double) * n);
      });
    return;
  }
  if (plane_group_ > 0) {
    // x and y transformed a group of planes at a time, then z: divided (or the Thomas sweeps
    // along it).
    planes(data, true, in);
    if (tri_axis_ == 2) tridiagonal(data, sigma);
    else transform(data, 2, true, sigma);
    planes(data, false, out);
    return;
  }
  if (tri_axis_ >= 0) {
    for (int a = 0; a < dim_; ++a)
      if (a != tri_axis_) transform(data, a, true, std::nullopt, a == 0 ? in : SolveIo{});
    tridiagonal(data, sigma);
    for (int a = dim_ - 1; a >= 0; --a)
      if (a != tri_axis_) transform(data, a, false, std::nullopt, a == 0 ? out : SolveIo{});
    return;
  }
  // Every axis transformed: along the last one forward, divided and back in one pass.
  const int last = dim_ - 1;
  for (int a = 0; a < last; ++a) transform(data, a, true, std::nullopt, a == 0 ? in : SolveIo{});
  transform(data, last, true, sigma);
  for (int a = last - 1; a >= 0; --a) transform(data, a, false, std::nullopt, a == 0 ? out : SolveIo{});
}

}  // namespace silt::fluid
