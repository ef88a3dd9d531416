// The lines of a block through the fast solver's transforms: gathered into a per-thread buffer
// (interleaved or transposed, reordered as the path wants), into the eigenbasis and back, and
// scattered into the data (fast_solver.hpp).
#include <cstring>
#include <optional>

#include "core/parallel.hpp"
#include "core/simd_level.hpp"
#include "fluid/fast_solver.hpp"
#include "fluid/fast_solver_plans.hpp"
#include "fluid/half_length_fft.hpp"
#include "fluid/sweep_for.hpp"

namespace silt::fluid {
namespace {

using Path = LinePath;

// A line of n points along x into the places of its path (place_point, place_sign), in loops of
// stride 1 or 2: the cosine and sine paths take the even points forward and the odd ones backward
// (negated for the sine), the face sine path shifts them by one place.
void line_into_places(Path path, const double* from, double* to, int64_t n) {
  if (path == Path::kFaceSine) {
    to[0] = 0;
    std::memcpy(to + 1, from, sizeof(double) * n);
    return;
  }
  const double odd = path == Path::kSine ? -1.0 : 1.0;
  for (int64_t r = 0; 2 * r < n; ++r) to[r] = from[2 * r];
  for (int64_t r = 0; 2 * r < n; ++r) to[n - 1 - r] = odd * from[2 * r + 1];
}

// And back (the cosine and sine paths).
void places_into_line(Path path, const double* from, double* to, int64_t n) {
  const double odd = path == Path::kSine ? -1.0 : 1.0;
  for (int64_t r = 0; 2 * r < n; ++r) to[2 * r] = from[r];
  for (int64_t r = 0; 2 * r < n; ++r) to[2 * r + 1] = odd * from[n - 1 - r];
}

}  // namespace

// A block of lines into the eigenbasis and back: along x kLinesX lines one after the other, along
// y and z kBlock lines, interleaved or one after the other. The packed order of a periodic line
// of even length n: Re 0, Re n/2, then Re p, Im p for p = 1 .. n/2 - 1. A half-length path: each line prepared, the
// block's complex transform, each line finished (half_length_fft.hpp). Forward: packed, and rotated into its cosine
// spectrum. Backward: rotated back and unpacked, then transformed. The face sine path, its own inverse, goes the same
// way both ways: prepared, transformed forward, packed and finished.
void FastSolver::through_modes(double* buf, int axis, bool forward) {
  const LinePath path = plans_->path[axis];
  if (!half_length(path)) {
    fftw_execute_r2r(forward ? plans_->fwd[axis] : plans_->bwd[axis], buf, buf);
    return;
  }
  const int64_t n = plans_->slots[axis];
  const double* w = plans_->twiddles[axis].data();
  const double* cw = plans_->cosines[axis].data();
  const double* sn = plans_->sines[axis].data();
  const bool cosine = cosine_like(path), face_sine = path == LinePath::kFaceSine;
  const bool fwd = forward || face_sine;
  // (lanes lines, cs values between their complex rows)
  auto before = [&](double* v, int64_t lanes, int64_t cs) {
    if (face_sine) face_sine_prepare(v, n, sn, lanes, cs);
    if (fwd) return;
    if (cosine) spectrum_from_cosine(v, n, cw, lanes, cs);
    unpack_spectrum(v, n, w, lanes, cs);
  };
  auto after = [&](double* v, int64_t lanes, int64_t cs) {
    if (!fwd) return;
    pack_spectrum(v, n, w, lanes, cs);
    if (cosine) cosine_from_spectrum(v, n, cw, lanes, cs);
    if (face_sine) face_sine_finish(v, n, lanes, cs);
  };
  const fftw_plan plan = fwd ? plans_->fwd[axis] : plans_->bwd[axis];
  if (plans_->interleaved[axis]) {
    const int64_t cs = plans_->row[axis];
    run_simd([&] { before(buf, kBlock, cs); });
    auto* c = reinterpret_cast<fftw_complex*>(buf);
    fftw_execute_dft(plan, c, c);
    run_simd([&] { after(buf, kBlock, cs); });
    return;
  }
  const int64_t lines = axis == 0 ? kLinesX : kBlock, g = plans_->group[axis], ls = plans_->stride[axis];
  for (int64_t first = 0; first < lines; first += g) {
    double* lines_of_group = buf + first * ls;
    run_simd([&] {
      for (int64_t b = 0; b < g; ++b) before(lines_of_group + b * ls, 1, 2);
    });
    auto* c = reinterpret_cast<fftw_complex*>(lines_of_group);
    fftw_execute_dft(plan, c, c);
    run_simd([&] {
      for (int64_t b = 0; b < g; ++b) after(lines_of_group + b * ls, 1, 2);
    });
  }
}

// Lines along `axis`, kBlock at a time: gathered into a buffer, transformed, scattered back.
// With divide_at (along y or z), each block is transformed forward, its modes divided and
// transformed back while it is in the buffer.
void FastSolver::transform(double* data, int axis, bool forward, std::optional<double> divide_at, const SolveIo& io,
                           PlaneRange planes) {
  // n points a line in the data, ns places in the buffer.
  const int64_t m0 = m_[0], m1 = m_[1], n = m_[axis], ns = plans_->slots[axis];
  const LinePath path = plans_->path[axis];
  // With divide_at the block goes forward and back in the buffer: in as forward, out as back.
  const bool reorder_in = reorders_in(path, forward), reorder_out = reorders_out(path, forward && !divide_at);
  if (axis == 0) {
    constexpr int B = kLinesX;
    const int64_t lines = m1 * m_[2], blocks = (lines + B - 1) / B;
    // A whole block aligned as the planner's buffer is transformed where it lies (when the path
    // moves no point).
    const int align = fftw_alignment_of(plans_->buffer());
    const bool in_place = ns == n && !reorder_in && !reorder_out;
    // Line l of the data, or of the rows read or written instead.
    auto line_of = [&](const SolveRows* rows, int64_t l) { return rows ? rows->line(l, m1) : data + l * n; };
    // The block of `count` lines from line `first`.
    auto block_of_lines = [&](double* buf, int64_t first, int64_t count) {
      double* block = data + first * n;
      if (count == B && fftw_alignment_of(block) == align && in_place) {
        // Read into the block, transformed and written out while it is in the cache.
        if (io.in)
          for (int64_t b = 0; b < count; ++b) {
            const double* from = line_of(io.in, first + b);
            double* to = block + b * n;
            for (int64_t r = 0; r < n; ++r) to[r] = from[r] * io.scale;
          }
        through_modes(block, axis, forward);
        if (io.out)
          for (int64_t b = 0; b < count; ++b)
            std::memcpy(line_of(io.out, first + b), block + b * n, sizeof(double) * n);
        return;
      }
      if (io.in) {
        // (scaled as it is read: each value times scale once, as a copy then a solve in place)
        for (int64_t b = 0; b < count; ++b) {
          double* to = buf + b * ns;
          if (!reorder_in) std::memcpy(to, line_of(io.in, first + b), sizeof(double) * n);
          else line_into_places(path, line_of(io.in, first + b), to, n);
          if (io.scale != 1.0)
            for (int64_t r = 0; r < ns; ++r) to[r] *= io.scale;
        }
      } else if (!reorder_in) {
        std::memcpy(buf, block, sizeof(double) * n * count);
      } else {
        for (int64_t b = 0; b < count; ++b) line_into_places(path, block + b * n, buf + b * ns, n);
      }
      if (count < B) std::memset(buf + count * ns, 0, sizeof(double) * (B - count) * ns);
      through_modes(buf, axis, forward);
      for (int64_t b = 0; b < count; ++b) {
        double* to = line_of(io.out, first + b);
        if (!reorder_out) std::memcpy(to, buf + b * ns, sizeof(double) * n);
        else places_into_line(path, buf + b * ns, to, n);
      }
    };
    if (planes.lo >= 0) {
      // The lines of the planes, B at a time from the first.
      double* buf = plans_->buffer();
      const int64_t end = planes.hi * m1;
      for (int64_t l = planes.lo * m1; l < end; l += B) block_of_lines(buf, l, std::min<int64_t>(B, end - l));
      return;
    }
    sweep_for(m_[0] * m_[1] * m_[2], blocks, 1, [&](int64_t b0, int64_t b1) {
      double* buf = plans_->buffer();
      for (int64_t blk = b0; blk < b1; ++blk) block_of_lines(buf, blk * B, std::min<int64_t>(B, lines - blk * B));
    });
    return;
  }
  // Along y or z: blocks of kBlock neighbouring x at one (other) index, copied into the buffer as
  // whole rows (place r of a line holding point r, or as the path reorders them). Short lines are
  // interleaved there, long ones (whose interleaved block would not stay in the first-level cache)
  // transposed. Lines past the grid's edge are zeros.
  constexpr int B = kBlock;
  const int64_t stride = axis == 1 ? m0 : m0 * m1;        // between points of a line
  const int64_t others = axis == 1 ? m_[2] : m1;          // the third index
  const int64_t other_stride = axis == 1 ? m0 * m1 : m0;  // its stride
  const int64_t xb = (m0 + B - 1) / B, blocks = xb * others;
  const bool packed = half_length(path), il = plans_->interleaved[axis];
  const int64_t ls = plans_->stride[axis];
  // Interleaved, a packed line's places 2k and 2k + 1 are one complex value: at k row + 2 b and
  // one further; other interleaved lines' place r at r row + b; transposed, at b ls + r.
  const int shift = il && packed ? 1 : 0;
  const int64_t row = il ? plans_->row[axis] : 1, lane = il ? (packed ? 2 : 1) : ls, odd = il && packed ? 1 : 0;
  const int64_t block_size = il ? (ns >> shift) * row : ls * B;
  auto run_blocks = [&](int64_t b0, int64_t b1) {
    double* buf = plans_->buffer();
    for (int64_t blk = b0; blk < b1; ++blk) {
      const int64_t i0 = (blk % xb) * B, o = blk / xb, count = std::min<int64_t>(B, m0 - i0);
      double* base = data + i0 + o * other_stride;
      if (count < B) std::memset(buf, 0, sizeof(double) * block_size);
      // Two rows of the data into one row of complex values, points 2k and 2k + 1 of each line
      // side by side (the interleaved packed block of a path that moves no point): strides known
      // to the compiler, which then vectorises the interleaving.
      const bool pairs_in = il && packed && !reorder_in && ns % 2 == 0;
      const bool pairs_out = il && packed && !reorder_out && n % 2 == 0;
      if (pairs_in) {
        for (int64_t r = 0; r < ns; r += 2) {
          const double* a = base + r * stride;
          const double* c = a + stride;
          double* to = buf + (r >> 1) * row;
          if (i0 + 2 * B <= m0)
            for (int64_t q = 0; q < B; q += 8) {
              __builtin_prefetch(a + B + q);
              __builtin_prefetch(c + B + q);
            }
          run_simd([&] {
            for (int64_t b = 0; b < count; ++b) {
              to[2 * b] = a[b];
              to[2 * b + 1] = c[b];
            }
          });
        }
      }
      // Place r of line b at (r >> shift) row + b lane + (r & odd).
      for (int64_t r = 0; r < (pairs_in ? 0 : ns); ++r) {
        const int64_t j = reorder_in ? place_point(path, r, n) : r;
        const double sg = reorder_in ? place_sign(path, r, n) : 1.0;
        double* to = buf + (r >> shift) * row + (r & odd);
        if (j < 0) {
          for (int64_t b = 0; b < count; ++b) to[b * lane] = 0;
          continue;
        }
        const double* from = base + j * stride;
        // The next block along x reads the same rows of the data, one block further: ask for
        // them now. Along z the rows are a plane apart, too far for the processor to guess (at
        // 256^3 on one thread, the pressure solves 10 % faster).
        if (i0 + 2 * B <= m0)
          for (int64_t c = 0; c < B; c += 8) __builtin_prefetch(from + B + c);
        for (int64_t b = 0; b < count; ++b) to[b * lane] = sg * from[b];
      }
      if (divide_at) {
        through_modes(buf, axis, true);
        divide_block(buf, axis, i0, count, o, *divide_at);
        through_modes(buf, axis, false);
      } else {
        through_modes(buf, axis, forward);
      }
      if (pairs_out) {
        for (int64_t r = 0; r < n; r += 2) {
          double* a = base + r * stride;
          double* c = a + stride;
          const double* from = buf + (r >> 1) * row;
          run_simd([&] {
            for (int64_t b = 0; b < count; ++b) {
              a[b] = from[2 * b];
              c[b] = from[2 * b + 1];
            }
          });
        }
        continue;
      }
      for (int64_t r = 0; r < n; ++r) {
        double* to = base + (reorder_out ? place_point(path, r, n) : r) * stride;
        const double sg = reorder_out ? place_sign(path, r, n) : 1.0;
        const double* from = buf + (r >> shift) * row + (r & odd);
        for (int64_t b = 0; b < count; ++b) to[b] = sg * from[b * lane];
      }
    }
  };
  // Along y, a plane's blocks are those of its z (o = the plane).
  if (planes.lo >= 0) run_blocks(planes.lo * xb, planes.hi * xb);
  else sweep_for(m_[0] * m_[1] * m_[2], blocks, 2, run_blocks);
}

}  // namespace silt::fluid
