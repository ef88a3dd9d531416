// The fast transform solver: (sigma - Lap_h) x = r for every axis kind, checked by applying the
// operator with the ghost rule of each kind, and against multigrid CG and a CHOLMOD direct solve
// of the assembled pressure matrix for each boundary type.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "fluid/fast_solver.hpp"
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

}  // namespace

// Even lengths take the real-to-complex transforms along a periodic axis, odd ones the halfcomplex
// pair: both orders of the modes are checked, along x, y and z.
TEST_CASE("fluid fast solver: every axis kind inverts its operator to round-off") {
  const AxisKind kinds[] = {AxisKind::kPeriodic, AxisKind::kCellNN, AxisKind::kCellDD, AxisKind::kCellND,
                            AxisKind::kCellDN,   AxisKind::kFaceDD, AxisKind::kFaceDN};
  unsigned seed = 1;
  for (int odd : {0, 1})
    for (int dim : {2, 3})
      for (AxisKind kx : kinds)
        for (AxisKind klast : kinds)
          for (double sigma : {0.0, 7.0}) {
            if (kx == AxisKind::kFaceDN && klast == AxisKind::kFaceDN) continue;  // one such axis at most
            std::array<SolverAxis, 3> ax{};
            ax[0] = {(dim == 2 ? 12 : 8) + odd, kx, 0.1};
            ax[1] = {(dim == 2 ? 10 : 6) + odd, dim == 2 ? klast : AxisKind::kCellDN, 0.1};
            ax[2] = {5 + odd, klast, 0.1};
            auto nn = [](AxisKind k) { return k == AxisKind::kPeriodic || k == AxisKind::kCellNN; };
            const bool singular = sigma == 0 && dim == 2 && nn(kx) && nn(klast);
            FastSolver solver(dim, ax);
            const auto r = random_field(static_cast<size_t>(solver.size()), seed++, singular);
            std::vector<double> x = r;
            solver.solve(x.data(), sigma);
            const auto back = apply(dim, ax, x, sigma);
            double scale = 0;
            for (double v : r) scale = std::max(scale, std::abs(v));
            INFO("dim " << dim << " odd " << odd << " kinds " << int(kx) << " " << int(klast) << " sigma " << sigma);
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
