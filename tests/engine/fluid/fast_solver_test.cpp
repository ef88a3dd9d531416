// The fast transform solver: (sigma - Lap_h) x = r for every axis kind, checked by applying the
// operator with the ghost rule of each kind, and against multigrid CG and a CHOLMOD direct solve
// of the assembled pressure matrix for each boundary type.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "fluid/fast_solver.hpp"
#include "fluid/half_length_fft.hpp"
#include "fluid/multigrid.hpp"
#include "fluid/poisson_operator.hpp"
#include "fluid/pressure_solve.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::fluid;
using silt::test::max_diff;

namespace {

// The value just outside the ends of a line of a given kind: periodic wraps; a Neumann end copies
// the last value; a Dirichlet face half a cell away negates it; a Dirichlet point one cell away
// is zero.
double outside(AxisKind k, const std::vector<double>& line, bool high) {
  const int64_t m = static_cast<int64_t>(line.size());
  const double end = high ? line[m - 1] : line[0];
  switch (k) {
    case AxisKind::kPeriodic: return high ? line[0] : line[m - 1];
    case AxisKind::kCellNN: return end;
    case AxisKind::kCellDD: return -end;
    case AxisKind::kCellND: return high ? -end : end;
    case AxisKind::kCellDN: return high ? end : -end;
    case AxisKind::kFaceDD: return 0;
    case AxisKind::kFaceDN: return high ? end : 0;
  }
  return 0;
}

// y = (sigma - Lap_h) x.
std::vector<double> apply(int dim, const std::array<SolverAxis, 3>& ax, const std::vector<double>& x, double sigma) {
  std::array<int64_t, 3> m{1, 1, 1};
  for (int a = 0; a < dim; ++a) m[a] = ax[a].m;
  std::vector<double> y(x.size());
  for (size_t q = 0; q < x.size(); ++q) y[q] = sigma * x[q];
  for (int a = 0; a < dim; ++a) {
    const int64_t stride = a == 0 ? 1 : (a == 1 ? m[0] : m[0] * m[1]);
    const double ih2 = 1 / (ax[a].h * ax[a].h);
    for (size_t q = 0; q < x.size(); ++q) {
      const int64_t i = (static_cast<int64_t>(q) / stride) % m[a];
      const int64_t base = static_cast<int64_t>(q) - i * stride;
      std::vector<double> line(m[a]);
      for (int64_t t = 0; t < m[a]; ++t) line[t] = x[base + t * stride];
      const double lo = i > 0 ? line[i - 1] : outside(ax[a].kind, line, false);
      const double hi = i < m[a] - 1 ? line[i + 1] : outside(ax[a].kind, line, true);
      y[q] -= (lo - 2 * line[i] + hi) * ih2;
    }
  }
  return y;
}

std::vector<double> random_field(size_t n, unsigned seed, bool zero_mean) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> v(n);
  double mean = 0;
  for (double& x : v) mean += (x = u(rng));
  if (zero_mean)
    for (double& x : v) x -= mean / static_cast<double>(n);
  return v;
}

Grid grid_with(int dim, std::array<int64_t, 3> n, std::array<std::array<BcType, 2>, 3> bc) {
  Grid g;
  g.dim = dim;
  g.n = n;
  if (dim == 2) g.n[2] = 1;
  g.h = {0.1, 0.1, 0.1};
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) g.bc[a][s].type = bc[a][s];
  return g;
}

// The real spectrum of v (even length n) by its definition, in the packed order: X_0, X_n/2, then
// Re X_k, Im X_k for k = 1 .. n/2 - 1.
std::vector<double> packed_real_spectrum(const std::vector<double>& v) {
  const auto n = static_cast<int64_t>(v.size());
  std::vector<double> out(v.size());
  for (int64_t k = 0; 2 * k <= n; ++k) {
    double re = 0, im = 0;
    for (int64_t j = 0; j < n; ++j) {
      const double t = 2 * std::numbers::pi * static_cast<double>(j * k % n) / static_cast<double>(n);
      re += v[j] * std::cos(t);
      im -= v[j] * std::sin(t);
    }
    if (k == 0) out[0] = re;
    else if (2 * k == n) out[1] = re;
    else out[2 * k] = re, out[2 * k + 1] = im;
  }
  return out;
}

// Every kind an axis can have.
constexpr AxisKind kAllKinds[] = {AxisKind::kPeriodic, AxisKind::kCellNN, AxisKind::kCellDD, AxisKind::kCellND,
                                  AxisKind::kCellDN,   AxisKind::kFaceDD, AxisKind::kFaceDN};

}  // namespace

// The packed spectrum of a real line through the complex transform of half its length, against
// the definition X_k = sum_j x_j exp(-2 pi i j k / n), and back (n x); the complex transforms of
// length n / 2 here are the definition too.
TEST_CASE("fluid fast solver: a real line's spectrum through a complex transform of half its length") {
  using C = std::complex<double>;
  auto dft = [](const std::vector<C>& z, double sign) {
    const auto N = static_cast<int64_t>(z.size());
    std::vector<C> out(z.size());
    for (int64_t k = 0; k < N; ++k)
      for (int64_t j = 0; j < N; ++j)
        out[k] += z[j] * std::polar(1.0, sign * 2 * std::numbers::pi * static_cast<double>(j * k % N) /
                                             static_cast<double>(N));
    return out;
  };
  unsigned seed = 3;
  // Above 128 a single line's pairs take more than one chunk of 32 (half_length_fft.hpp).
  for (int64_t n : {2, 4, 6, 8, 10, 12, 16, 30, 64, 128, 130, 132, 194, 256}) {
    const auto x = random_field(static_cast<size_t>(n), seed++, false);
    const auto w = half_length_twiddles(n);
    std::vector<C> z(static_cast<size_t>(n / 2));
    for (int64_t k = 0; k < n / 2; ++k) z[k] = {x[2 * k], x[2 * k + 1]};
    z = dft(z, -1);
    std::vector<double> line(static_cast<size_t>(n));
    for (int64_t k = 0; k < n / 2; ++k) line[2 * k] = z[k].real(), line[2 * k + 1] = z[k].imag();
    pack_spectrum(line.data(), n, w.data());
    std::vector<C> xc(x.begin(), x.end());
    const auto X = dft(xc, -1);
    INFO("n " << n);
    CHECK(std::abs(line[0] - X[0].real()) < 1e-12 * n);
    CHECK(std::abs(line[1] - X[n / 2].real()) < 1e-12 * n);
    for (int64_t k = 1; k < n / 2; ++k) {
      CHECK(std::abs(line[2 * k] - X[k].real()) < 1e-12 * n);
      CHECK(std::abs(line[2 * k + 1] - X[k].imag()) < 1e-12 * n);
    }
    // Three lines interleaved in rows of 8 values (complex k of line l at 8 k + 2 l, two values
    // of padding a row, which stay as they are): each as the line alone.
    constexpr int64_t kRow = 8;
    constexpr double kPad = 7.25;
    std::vector<double> three(static_cast<size_t>(kRow * n / 2), kPad);
    for (int64_t k = 0; k < n / 2; ++k)
      for (int64_t l = 0; l < 3; ++l) {
        const double f = 1.0 + static_cast<double>(l);  // line l holds (1 + l) z
        three[kRow * k + 2 * l] = f * z[k].real(), three[kRow * k + 2 * l + 1] = f * z[k].imag();
      }
    pack_spectrum(three.data(), n, w.data(), 3, kRow);
    auto check_three = [&](double tolerance) {
      for (int64_t k = 0; k < n / 2; ++k) {
        for (int64_t l = 0; l < 3; ++l)
          for (int64_t r = 0; r < 2; ++r)
            CHECK(std::abs(three[kRow * k + 2 * l + r] - (1.0 + l) * line[2 * k + r]) < tolerance);
        CHECK(three[kRow * k + 6] == kPad);
        CHECK(three[kRow * k + 7] == kPad);
      }
    };
    check_three(1e-12 * n);
    unpack_spectrum(three.data(), n, w.data(), 3, kRow);
    unpack_spectrum(line.data(), n, w.data());
    check_three(1e-12 * n * n);
    for (int64_t k = 0; k < n / 2; ++k) z[k] = {line[2 * k], line[2 * k + 1]};
    z = dft(z, 1);
    for (int64_t k = 0; k < n / 2; ++k) {
      CHECK(std::abs(z[k].real() - n * x[2 * k]) < 1e-12 * n * n);
      CHECK(std::abs(z[k].imag() - n * x[2 * k + 1]) < 1e-12 * n * n);
    }
  }
}

// The cosine transform through the real one (Makhoul): reordered points, the real spectrum in
// packed order, rotated, against the definition Y_q = 2 sum_j x_j cos(pi q (j + 1/2) / n) at the
// place of each mode q; and back to 2n x.
TEST_CASE("fluid fast solver: the cosine transform of a line through its real spectrum") {
  unsigned seed = 5;
  for (int64_t n : {2, 4, 6, 8, 10, 16, 30, 64, 130, 256}) {
    const auto x = random_field(static_cast<size_t>(n), seed++, false);
    std::vector<double> v(static_cast<size_t>(n));
    for (int64_t r = 0; r < n; ++r) v[r] = x[cosine_source(r, n)];
    std::vector<double> line = packed_real_spectrum(v);
    const auto c = cosine_twiddles(n);
    std::vector<double> spectrum = line;
    cosine_from_spectrum(line.data(), n, c.data());
    INFO("n " << n);
    for (int64_t p = 0; p < n; ++p) {
      const int64_t q = cosine_mode(p, n);
      double y = 0;
      for (int64_t j = 0; j < n; ++j)
        y += 2 * x[j] *
             std::cos(std::numbers::pi * static_cast<double>(q) * (static_cast<double>(j) + 0.5) /
                      static_cast<double>(n));
      CHECK(std::abs(line[p] - y) < 1e-12 * n);
    }
    // Every mode once.
    std::vector<int> seen(static_cast<size_t>(n), 0);
    for (int64_t p = 0; p < n; ++p) ++seen[cosine_mode(p, n)];
    for (int s : seen) CHECK(s == 1);
    spectrum_from_cosine(line.data(), n, c.data());
    for (int64_t p = 0; p < n; ++p) CHECK(std::abs(line[p] - 2 * spectrum[p]) < 1e-12 * n);
  }
}

// The sine transform of interior faces through the real transform of m + 1 places: the prepared
// line's real spectrum (by its definition) finished into Y_k = 2 sum_j x_j sin(pi (j + 1) (k + 1)
// / (m + 1)) at place k, one line and three interleaved; and applied twice, 2 (m + 1) x.
TEST_CASE("fluid fast solver: the sine transform of interior faces through a real spectrum") {
  unsigned seed = 9;
  for (int64_t m : {1, 3, 5, 7, 15, 31, 63}) {
    const int64_t N = m + 1;
    const auto x = random_field(static_cast<size_t>(m), seed++, false);
    const auto sn = face_sine_table(N);
    auto transform = [&](const std::vector<double>& in) {  // in: m values; out: N places
      std::vector<double> v(static_cast<size_t>(N), 0.0);
      for (int64_t j = 0; j < m; ++j) v[j + 1] = in[j];
      face_sine_prepare(v.data(), N, sn.data());
      v = packed_real_spectrum(v);
      face_sine_finish(v.data(), N);
      return v;
    };
    const auto y = transform(x);
    INFO("m " << m);
    for (int64_t k = 0; k < m; ++k) {
      double d = 0;
      for (int64_t j = 0; j < m; ++j)
        d += 2 * x[j] * std::sin(std::numbers::pi * static_cast<double>((j + 1) * (k + 1)) / static_cast<double>(N));
      CHECK(std::abs(y[k] - d) < 1e-12 * N);
    }
    CHECK(y[m] == 0.0);
    // Three lines interleaved in rows of 8 values (place r of line l at 8 (r / 2) + 2 l + r % 2,
    // two values of padding a row, which stay as they are): each as alone.
    constexpr int64_t kRow = 8;
    constexpr double kPad = 7.25;
    std::vector<double> three(static_cast<size_t>(kRow * N / 2), kPad);
    auto at = [](int64_t r, int64_t l) { return kRow * (r / 2) + 2 * l + r % 2; };
    for (int64_t l = 0; l < 3; ++l)
      for (int64_t j = 0; j < m; ++j) three[at(j + 1, l)] = (1.0 + l) * x[j];
    face_sine_prepare(three.data(), N, sn.data(), 3, kRow);
    for (int64_t l = 0; l < 3; ++l) {
      std::vector<double> v(static_cast<size_t>(N));
      for (int64_t r = 0; r < N; ++r) v[r] = three[at(r, l)];
      v = packed_real_spectrum(v);
      for (int64_t r = 0; r < N; ++r) three[at(r, l)] = v[r];
    }
    face_sine_finish(three.data(), N, 3, kRow);
    for (int64_t l = 0; l < 3; ++l)
      for (int64_t k = 0; k < N; ++k) CHECK(std::abs(three[at(k, l)] - (1.0 + l) * y[k]) < 1e-12 * N);
    for (int64_t k = 0; k < N / 2; ++k) CHECK((three[kRow * k + 6] == kPad && three[kRow * k + 7] == kPad));
    std::vector<double> yk(y.begin(), y.begin() + m);
    const auto back = transform(yk);
    for (int64_t j = 0; j < m; ++j) CHECK(std::abs(back[j] - 2.0 * N * x[j]) < 1e-11 * N * N);
  }
}

// Periodic, cell NN, cell DD and face DD lines as short as 2 and 4 points, odd and even, along x, y and z
// (the last one solved by Thomas when not periodic), in blocks that fill the transforms' buffers
// and blocks that do not.
TEST_CASE("fluid fast solver: periodic axes of every short even length and of odd lengths invert to round-off") {
  unsigned seed = 11;
  // Along y and z, lines of up to 128 points are interleaved; so are the lines of these kinds'
  // complex paths (periodic, cell NN and DD of even length, face DD of odd) of up to 1024 places,
  // in padded rows; other lines are transposed.
  const std::array<int64_t, 3> sizes[] = {{2, 4, 4},   {3, 5, 4},    {4, 6, 4},    {5, 7, 4},    {6, 8, 4},
                                          {16, 18, 4}, {34, 36, 4},  {3, 136, 6},  {4, 135, 4},  {5, 4, 137},
                                          {4, 2, 130}, {3, 1024, 2}, {2, 1023, 2}, {3, 2, 1026}, {2, 2, 1025}};
  for (AxisKind kind : {AxisKind::kPeriodic, AxisKind::kCellNN, AxisKind::kCellDD, AxisKind::kFaceDD})
    for (const auto& m : sizes)
      for (double sigma : {0.0, 3.0}) {
        std::array<SolverAxis, 3> ax{};
        for (int a = 0; a < 3; ++a) ax[a] = {m[a], kind, 0.1};
        FastSolver solver(3, ax);
        const auto r = random_field(static_cast<size_t>(solver.size()), seed++, sigma == 0);
        std::vector<double> x = r;
        solver.solve(x.data(), sigma);
        const auto back = apply(3, ax, x, sigma);
        double scale = 0;
        for (double v : r) scale = std::max(scale, std::abs(v));
        INFO("kind " << int(kind) << " m " << m[0] << " " << m[1] << " " << m[2] << " sigma " << sigma);
        CHECK(max_diff(back, r) < 1e-10 * scale);
      }
}

// Even lengths take the half-length complex transforms along a periodic axis, odd ones the halfcomplex
// pair: both orders of the modes are checked, along x, y and z. The second 3D box goes along x and
// y two z planes at a time (32 lines along x to a plane), its last group one plane when odd.
TEST_CASE("fluid fast solver: every axis kind inverts its operator to round-off") {
  unsigned seed = 1;
  for (int odd : {0, 1})
    for (int shape : {2, 3, 4})
      for (AxisKind kx : kAllKinds)
        for (AxisKind klast : kAllKinds)
          for (double sigma : {0.0, 7.0}) {
            if (kx == AxisKind::kFaceDN && klast == AxisKind::kFaceDN) continue;  // one such axis at most
            const int dim = shape == 2 ? 2 : 3;
            std::array<SolverAxis, 3> ax{};
            ax[0] = {(dim == 2 ? 12 : 8) + odd, kx, 0.1};
            ax[1] = {shape == 4 ? 32 : (dim == 2 ? 10 : 6) + odd, dim == 2 ? klast : AxisKind::kCellDN, 0.1};
            ax[2] = {(shape == 4 ? 9 : 5) + odd, klast, 0.1};
            auto nn = [](AxisKind k) { return k == AxisKind::kPeriodic || k == AxisKind::kCellNN; };
            const bool singular = sigma == 0 && dim == 2 && nn(kx) && nn(klast);
            FastSolver solver(dim, ax);
            const auto r = random_field(static_cast<size_t>(solver.size()), seed++, singular);
            std::vector<double> x = r;
            solver.solve(x.data(), sigma);
            const auto back = apply(dim, ax, x, sigma);
            double scale = 0;
            for (double v : r) scale = std::max(scale, std::abs(v));
            INFO("shape " << shape << " odd " << odd << " kinds " << int(kx) << " " << int(klast) << " sigma "
                          << sigma);
            CHECK(max_diff(back, r) < 1e-10 * scale);
          }
}

TEST_CASE("fluid fast solver: the pressure solve agrees with multigrid CG and with CHOLMOD for each boundary type") {
  using B = BcType;
  const std::array<std::array<std::array<BcType, 2>, 3>, 4> cases = {{
      {{{B::kPeriodic, B::kPeriodic}, {B::kPeriodic, B::kPeriodic}, {B::kPeriodic, B::kPeriodic}}},
      {{{B::kNoSlip, B::kNoSlip}, {B::kNoSlip, B::kNoSlip}, {B::kNoSlip, B::kNoSlip}}},
      {{{B::kInflow, B::kOutflow}, {B::kNoSlip, B::kFreeSlip}, {B::kNoSlip, B::kNoSlip}}},
      {{{B::kPeriodic, B::kPeriodic}, {B::kNoSlip, B::kNoSlip}, {B::kPeriodic, B::kPeriodic}}},
  }};
  for (int dim : {2, 3})
    for (size_t c = 0; c < cases.size(); ++c) {
      const Grid g = grid_with(dim, {12, 8, 6}, cases[c]);
      const bool singular = poisson_singular(g, 0.0);
      const auto r = random_field(static_cast<size_t>(g.cells()), 40 + static_cast<unsigned>(c), singular);
      // Transforms.
      FastSolver fast(dim, pressure_axes(g));
      std::vector<double> x_fast = r;
      fast.solve(x_fast.data(), 0.0);
      // Multigrid CG to 1e-12.
      PoissonSolverOptions opt;
      opt.cg = {1e-12, 500};
      PoissonSolver mg(g, 0.0, opt);
      const linalg::Vector b = Eigen::Map<const linalg::Vector>(r.data(), static_cast<Eigen::Index>(r.size()));
      linalg::Vector x_mg;
      REQUIRE(mg.solve(b, x_mg).ok());
      // CHOLMOD on the assembled matrix (the first cell pinned when singular).
      linalg::CholeskyFactor chol;
      const linalg::SparseMatrix a = assemble_poisson(g, 0.0, singular);
      REQUIRE(chol.factorize(a).ok());
      linalg::Vector bb = b;
      if (singular) bb[0] = 0;
      linalg::Vector x_direct;
      REQUIRE(chol.solve(bb, x_direct).ok());
      // Compare up to the constant of the singular case.
      auto centred = [&](std::vector<double> v) {
        double mean = 0;
        for (double e : v) mean += e;
        mean /= static_cast<double>(v.size());
        if (singular)
          for (double& e : v) e -= mean;
        return v;
      };
      const auto f = centred(x_fast);
      const auto m = centred(std::vector<double>(x_mg.data(), x_mg.data() + x_mg.size()));
      const auto d = centred(std::vector<double>(x_direct.data(), x_direct.data() + x_direct.size()));
      double scale = 0;
      for (double e : d) scale = std::max(scale, std::abs(e));
      INFO("dim " << dim << " case " << c);
      CHECK(max_diff(f, d) < 1e-10 * scale);
      CHECK(max_diff(m, d) < 1e-8 * scale);
    }
}

TEST_CASE("fluid fast solver: Helmholtz against a manufactured solution") {
  // (sigma - Lap) x = r with x = sin(pi (i + 1) / n) cos(2 pi (j + 1/2) / m) on the interior
  // faces of a wall-bounded x and a periodic y: r = (sigma + lambda_x + lambda_y) x exactly, so the
  // solver must return x from r.
  const int64_t n = 16, m = 12;
  const double h = 0.05, sigma = 3.0;
  std::array<SolverAxis, 3> ax{};
  ax[0] = {n - 1, AxisKind::kFaceDD, h};
  ax[1] = {m, AxisKind::kPeriodic, h};
  FastSolver solver(2, ax);
  const double pi = std::acos(-1.0);
  const double lx = (2 - 2 * std::cos(pi / n)) / (h * h), ly = (2 - 2 * std::cos(2 * pi / m)) / (h * h);
  std::vector<double> x(static_cast<size_t>((n - 1) * m)), r(x.size());
  for (int64_t j = 0; j < m; ++j)
    for (int64_t i = 0; i < n - 1; ++i) {
      const double v = std::sin(pi * (i + 1) / n) * std::cos(2 * pi * (j + 0.5) / m);
      x[i + (n - 1) * j] = v;
      r[i + (n - 1) * j] = (sigma + lx + ly) * v;
    }
  solver.solve(r.data(), sigma);
  CHECK(max_diff(r, x) < 1e-13);
}

// A solve that reads its right-hand side from the rows of a padded field (times a scale) and writes
// the solution back there gives, bit for bit, the copy-in, solve-in-place, copy-out it replaces;
// for every kind along x (the Thomas sweeps along x copy), odd and even lengths, blocks of lines full
// and partial, lines along y interleaved and transposed.
TEST_CASE("fluid fast solver: a solve through a padded field's rows equals copying in and out") {
  unsigned seed = 100;
  for (int odd : {0, 1})
    for (int shape : {2, 3, 4})
      for (AxisKind kx : kAllKinds)
        for (AxisKind klast : {AxisKind::kPeriodic, AxisKind::kCellDD, AxisKind::kFaceDN}) {
          if (kx == AxisKind::kFaceDN && klast == AxisKind::kFaceDN) continue;
          const int dim = shape == 2 ? 2 : 3;
          std::array<SolverAxis, 3> ax{};
          ax[0] = {(dim == 2 ? 12 : 8) + odd, kx, 0.1};
          // In 2D 130 lines along x (blocks full and partial) and lines of 130 along y (transposed);
          // the second 3D box along x and y two z planes at a time.
          ax[1] = {dim == 2 ? 130 : (shape == 4 ? 32 : 9), dim == 2 ? klast : AxisKind::kCellNN, 0.1};
          ax[2] = {dim == 2 ? 1 : (shape == 4 ? 9 : 10) + odd, klast, 0.1};
          FastSolver solver(dim, ax);
          const int64_t m0 = ax[0].m, m1 = ax[1].m, m2 = dim == 3 ? ax[2].m : 1;
          const int64_t row = m0 + 3, plane = row * (m1 + 3);
          const double sigma = 7.0, scale = 1.0 / 3.0;
          std::vector<double> field = random_field(static_cast<size_t>(plane * (m2 + 3)), seed++, false);
          const int64_t origin = 1 + row + (dim == 3 ? plane : 0);
          std::vector<double> x(static_cast<size_t>(solver.size()));
          for (int64_t k = 0; k < m2; ++k)
            for (int64_t j = 0; j < m1; ++j)
              for (int64_t i = 0; i < m0; ++i)
                x[i + m0 * (j + m1 * k)] = field[origin + i + j * row + k * plane] * scale;
          solver.solve(x.data(), sigma);
          std::vector<double> expected = field;
          for (int64_t k = 0; k < m2; ++k)
            for (int64_t j = 0; j < m1; ++j)
              for (int64_t i = 0; i < m0; ++i) expected[origin + i + j * row + k * plane] = x[i + m0 * (j + m1 * k)];
          const SolveRows rows{field.data() + origin, row, dim == 3 ? plane : 0};
          std::vector<double> work(static_cast<size_t>(solver.size()));
          solver.solve(work.data(), sigma, {&rows, scale, &rows});
          INFO("shape " << shape << " odd " << odd << " kinds " << int(kx) << " " << int(klast));
          CHECK(field == expected);  // the ghosts untouched, every unknown to the bit
        }
}
