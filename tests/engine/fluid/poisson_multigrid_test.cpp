// The cell-centred pressure operator and its multigrid-preconditioned CG: the kernel against
// closed forms on a small patch, the matrix-free product against the assembled matrix, MGPCG
// against the CHOLMOD direct solve for every kind of boundary in 2D and 3D, the V-cycle as a
// symmetric positive definite map, iteration counts independent of the grid, the Helmholtz
// operator against its discrete eigenfunction, and the same bits on 1 and 2 threads.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "fluid/multigrid.hpp"
#include "fluid/poisson_kernels.hpp"
#include "fluid/poisson_operator.hpp"
#include "silt/linalg.hpp"
#include "support/scenes.hpp"

using namespace silt::fluid;
using silt::linalg::Vector;
using silt::test::gaussian_vector;
using silt::test::rel_diff;

namespace {

enum class Boxes { kPeriodic, kNeumann, kDirichletFace, kPeriodicX };
const char* boxes_name(Boxes b) {
  switch (b) {
    case Boxes::kPeriodic: return "all periodic";
    case Boxes::kNeumann: return "all Neumann";
    case Boxes::kDirichletFace: return "Dirichlet on x high, Neumann elsewhere";
    case Boxes::kPeriodicX: return "periodic x, Neumann elsewhere";
  }
  return "?";
}
constexpr Boxes kAllBoxes[] = {Boxes::kPeriodic, Boxes::kNeumann, Boxes::kDirichletFace, Boxes::kPeriodicX};

// Walls give Neumann pressure faces, an outflow a Dirichlet one.
Grid make_grid(int dim, std::array<int64_t, 3> n, std::array<double, 3> h, Boxes boxes) {
  Grid g;
  g.dim = dim;
  g.n = n;
  g.h = h;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      BcType t = BcType::kNoSlip;
      if (a >= dim || boxes == Boxes::kPeriodic || (boxes == Boxes::kPeriodicX && a == 0)) t = BcType::kPeriodic;
      if (boxes == Boxes::kDirichletFace && a == 0 && side == 1) t = BcType::kOutflow;
      g.bc[a][side].type = t;
    }
  return g;
}

Grid grid_2d(Boxes b) { return make_grid(2, {16, 12, 1}, {0.1, 0.12, 1}, b); }
Grid grid_3d(Boxes b) { return make_grid(3, {8, 8, 6}, {0.1, 0.09, 0.12}, b); }

void remove_mean(Vector& v) { v.array() -= v.mean(); }

// The direct reference: CHOLMOD on the assembled matrix; in the singular case on the matrix with
// its first cell pinned, with b of zero mean, and the zero-mean representative returned.
Vector direct_solve(const Grid& g, double sigma, Vector b) {
  const bool singular = poisson_singular(g, sigma);
  silt::linalg::CholeskyFactor f;
  REQUIRE(f.factorize(assemble_poisson(g, sigma, singular)).ok());
  if (singular) {
    remove_mean(b);
    b[0] = 0;
  }
  Vector x;
  REQUIRE(f.solve(b, x).ok());
  if (singular) remove_mean(x);
  return x;
}

}  // namespace

TEST_CASE("fluid poisson: the kernel on a 3x3x3 patch against closed forms") {
  // The 7-point Laplacian is exact on quadratics: at the centre of the patch,
  // -Lap (x^2 + 2 y^2 - z^2) = -(2 + 4 - 2) = -4, and A p = sigma p - 4.
  const std::array<double, 3> h{0.5, 0.25, 2.0};
  const Grid g = make_grid(3, {3, 3, 3}, h, Boxes::kNeumann);
  const double sigma = 0.7;
  const PoissonStencil s = make_poisson_stencil(g, sigma);
  std::vector<double> p(27), one(27, 1.0);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const double x = (i + 0.5) * h[0], y = (j + 0.5) * h[1], z = (k + 0.5) * h[2];
        p[static_cast<size_t>(i + 3 * (j + 3 * k))] = x * x + 2 * y * y - z * z;
      }
  CHECK(poisson_apply_at(s, 1, 1, 1, p.data()) == doctest::Approx(sigma * p[13] - 4).epsilon(1e-13));
  CHECK(poisson_diagonal_at(s, 1, 1, 1) == doctest::Approx(sigma + 2 / 0.25 + 2 / 0.0625 + 2 / 4.0));
  // Constants: Neumann faces see no difference, a Dirichlet face (p = 0 half a cell out) sees
  // the jump from 1 to the ghost -1 over h^2: 2 / h^2 in the cells along it.
  const PoissonStencil n0 = make_poisson_stencil(g, 0);
  for (int64_t c = 0; c < 27; ++c) CHECK(poisson_apply_at(n0, c % 3, (c / 3) % 3, c / 9, one.data()) == 0);
  const PoissonStencil d0 = make_poisson_stencil(make_grid(3, {3, 3, 3}, h, Boxes::kDirichletFace), 0);
  CHECK(poisson_apply_at(d0, 2, 1, 1, one.data()) == doctest::Approx(2 / 0.25));
  CHECK(poisson_apply_at(d0, 1, 1, 1, one.data()) == 0);
  CHECK(poisson_diagonal_at(d0, 2, 0, 0) == doctest::Approx(3 / 0.25 + 1 / 0.0625 + 1 / 4.0));
  // Periodic: cell 0's low neighbour is cell 2.
  const PoissonStencil per = make_poisson_stencil(make_grid(3, {3, 3, 3}, h, Boxes::kPeriodic), 0);
  std::vector<double> e(27, 0.0);
  e[2] = 1;  // (2, 0, 0)
  CHECK(poisson_apply_at(per, 0, 0, 0, e.data()) == doctest::Approx(-1 / 0.25));
}

TEST_CASE("fluid poisson: the matrix-free operator equals the assembled matrix") {
  for (int dim : {2, 3})
    for (Boxes boxes : kAllBoxes)
      for (double sigma : {0.0, 3.5}) {
        CAPTURE(dim);
        CAPTURE(boxes_name(boxes));
        CAPTURE(sigma);
        const Grid g = dim == 2 ? grid_2d(boxes) : grid_3d(boxes);
        const PoissonOperator op(g, sigma);
        const silt::linalg::SparseMatrix a = assemble_poisson(g, sigma);
        CHECK((a - silt::linalg::SparseMatrix(a.transpose())).norm() == 0);
        const Vector x = gaussian_vector(op.size(), 7);
        Vector y;
        op.apply(x, y);
        const Vector ya = a * x;
        CHECK(rel_diff(y, ya) < 1e-14);
        for (int64_t c = 0; c < op.size(); c += 7) {
          const int64_t i = c % g.n[0], j = (c / g.n[0]) % g.n[1], k = c / (g.n[0] * g.n[1]);
          CHECK(poisson_diagonal_at(op.stencil(), i, j, k) == doctest::Approx(a.coeff(c, c)).epsilon(1e-14));
        }
        // The constants are the null space exactly when the operator is said singular.
        op.apply(Vector::Ones(op.size()), y);
        CHECK((y.norm() < 1e-9) == op.singular());
      }
}

TEST_CASE("fluid poisson: multigrid CG agrees with the CHOLMOD direct solve") {
  PoissonSolverOptions opt;
  opt.cg = {1e-12, 100};
  for (int dim : {2, 3})
    for (Boxes boxes : kAllBoxes)
      for (Prolongation pro : {Prolongation::kConstant, Prolongation::kLinear}) {
        CAPTURE(dim);
        CAPTURE(boxes_name(boxes));
        CAPTURE(static_cast<int>(pro));
        const Grid g = dim == 2 ? grid_2d(boxes) : grid_3d(boxes);
        opt.multigrid.prolongation = pro;
        PoissonSolver solver(g, 0, opt);
        CHECK(solver.preconditioner().levels() >= 2);
        // b of nonzero mean: in the singular case both solvers drop it
        const Vector b = gaussian_vector(g.cells(), 11);
        Vector x;
        const silt::linalg::SolveReport rep = solver.solve(b, x);
        CHECK(rep.ok());
        CHECK(rel_diff(x, direct_solve(g, 0, b)) < 1e-9);
      }
  // An odd periodic count on the coarsest level, factored, or relaxed by damped Jacobi (no
  // red-black colouring there).
  const Grid odd = make_grid(2, {30, 14, 1}, {0.1, 0.1, 1}, Boxes::kPeriodic);
  for (int64_t direct : {int64_t{16384}, int64_t{0}}) {
    CAPTURE(direct);
    opt.multigrid = {};
    opt.multigrid.max_direct_cells = direct;
    PoissonSolver solver(odd, 0, opt);
    CHECK(solver.preconditioner().levels() == 2);
    CHECK(solver.preconditioner().direct_coarsest() == (direct > 0));
    const Vector b = gaussian_vector(odd.cells(), 19);
    Vector x;
    CHECK(solver.solve(b, x).ok());
    CHECK(rel_diff(x, direct_solve(odd, 0, b)) < 1e-9);
  }
}

TEST_CASE("fluid poisson: the V-cycle is a symmetric positive definite map") {
  // u . M^-1 v = v . M^-1 u and u . M^-1 u > 0 (on the zero-mean vectors when A is singular),
  // for both prolongations, and with a coarsest level relaxed instead of factored; an odd
  // periodic coarsest level has no red-black colouring and is relaxed by damped Jacobi.
  struct Case {
    Grid g;
    MultigridOptions o;
  };
  std::vector<Case> cases;
  for (Boxes boxes : kAllBoxes)
    for (Prolongation pro : {Prolongation::kConstant, Prolongation::kLinear})
      for (int64_t direct : {int64_t{16384}, int64_t{0}}) {
        MultigridOptions o;
        o.prolongation = pro;
        o.max_direct_cells = direct;
        o.coarse_sweeps = 4;
        cases.push_back({grid_2d(boxes), o});
        cases.push_back({grid_3d(boxes), o});
      }
  MultigridOptions jacobi;
  jacobi.max_direct_cells = 0;
  jacobi.coarsest_cells = 100;
  cases.push_back({make_grid(2, {30, 30, 1}, {0.1, 0.1, 1}, Boxes::kPeriodic), jacobi});  // 15 x 15 coarsest
  for (const Case& c : cases) {
    const MultigridPreconditioner mg(c.g, 0, c.o);
    CAPTURE(c.g.n[0]);
    CAPTURE(c.g.pbc(0, 1));
    CAPTURE(c.o.max_direct_cells);
    Vector u = gaussian_vector(c.g.cells(), 3), v = gaussian_vector(c.g.cells(), 4), mu, mv;
    mg.remove_mean(u);
    mg.remove_mean(v);
    mg.apply(u, mu);
    mg.apply(v, mv);
    CHECK(std::abs(u.dot(mv) - v.dot(mu)) < 1e-12 * u.norm() * mv.norm());
    CHECK(u.dot(mu) > 0);
    CHECK(v.dot(mv) > 0);
  }
}

TEST_CASE("fluid poisson: CG iterations with the V-cycle do not grow with the grid") {
  PoissonSolverOptions opt;
  opt.cg = {1e-8, 100};
  for (int dim : {2, 3})
    for (Boxes boxes : {Boxes::kNeumann, Boxes::kDirichletFace, Boxes::kPeriodicX}) {
      std::vector<int> its;
      const std::vector<int64_t> sides = dim == 2 ? std::vector<int64_t>{32, 64, 128} : std::vector<int64_t>{16, 32};
      for (int64_t m : sides) {
        const double h = 1.0 / static_cast<double>(m);
        const Grid g = make_grid(dim, {m, m, dim == 3 ? m : 1}, {h, h, h}, boxes);
        PoissonSolver solver(g, 0, opt);
        Vector x;
        const silt::linalg::SolveReport rep = solver.solve(gaussian_vector(g.cells(), 5), x);
        CHECK(rep.ok());
        its.push_back(rep.iterations);
      }
      std::string s;
      for (size_t q = 0; q < its.size(); ++q)
        s += std::to_string(sides[q]) + "^" + std::to_string(dim) + ": " + std::to_string(its[q]) + " iterations  ";
      const std::string line = std::string(boxes_name(boxes)) + ": " + s;
      INFO(line);
      for (int it : its) CHECK(it <= 15);
      CHECK(its.back() - its.front() <= 3);
    }
}

TEST_CASE("fluid poisson: Helmholtz against its discrete eigenfunction") {
  // On a periodic box, p = cos(2 pi x / Lx) sin(2 pi y / Ly) at the cell centres is an
  // eigenvector of A: along x, cos(t (x + h)) + cos(t (x - h)) = 2 cos(t h) cos(t x), so the
  // 3-point difference gives (2 - 2 cos(2 pi h / L)) / h^2 times p, and likewise along y; hence
  // A p = lambda p with lambda = sigma + (2 - 2 cos(2 pi hx / Lx)) / hx^2 + (same in y).
  const double pi = std::numbers::pi;
  const double lx = 1.0, ly = 0.75, sigma = 40.0;
  const Grid g = make_grid(2, {32, 16, 1}, {lx / 32, ly / 16, 1}, Boxes::kPeriodic);
  const double hx = g.h[0], hy = g.h[1];
  const double lambda =
      sigma + (2 - 2 * std::cos(2 * pi * hx / lx)) / (hx * hx) + (2 - 2 * std::cos(2 * pi * hy / ly)) / (hy * hy);
  Vector p(g.cells());
  for (int64_t j = 0; j < g.n[1]; ++j)
    for (int64_t i = 0; i < g.n[0]; ++i)
      p[g.cell(i, j)] = std::cos(2 * pi * (i + 0.5) * hx / lx) * std::sin(2 * pi * (j + 0.5) * hy / ly);
  PoissonSolverOptions opt;
  opt.cg = {1e-12, 100};
  PoissonSolver solver(g, sigma, opt);
  CHECK_FALSE(solver.op().singular());
  Vector x;
  const silt::linalg::SolveReport rep = solver.solve(lambda * p, x);
  CHECK(rep.ok());
  CHECK((x - p).lpNorm<Eigen::Infinity>() < 1e-9);
  // and against the direct solve, on a 3D box with a Dirichlet face
  const Grid g3 = grid_3d(Boxes::kDirichletFace);
  PoissonSolver s3(g3, sigma, opt);
  const Vector b = gaussian_vector(g3.cells(), 13);
  CHECK(s3.solve(b, x).ok());
  CHECK(rel_diff(x, direct_solve(g3, sigma, b)) < 1e-9);
}

TEST_CASE("fluid poisson: the same bits on 1 and 2 threads") {
  // Grids of several tasks per sweep and several blocks per dot product.
  for (const Grid& g : {make_grid(2, {128, 64, 1}, {0.01, 0.01, 1}, Boxes::kDirichletFace),
                        make_grid(3, {32, 16, 16}, {0.02, 0.02, 0.02}, Boxes::kPeriodicX)}) {
    const Vector b = gaussian_vector(g.cells(), 17);
    Vector x[2];
    silt::linalg::SolveReport rep[2];
    for (int t = 0; t < 2; ++t) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(t + 1));
      PoissonSolver solver(g);
      rep[t] = solver.solve(b, x[t]);
      CHECK(rep[t].ok());
    }
    CHECK(rep[0].iterations == rep[1].iterations);
    CHECK(std::memcmp(&rep[0].residual, &rep[1].residual, sizeof(double)) == 0);
    CHECK(std::memcmp(x[0].data(), x[1].data(), sizeof(double) * static_cast<size_t>(x[0].size())) == 0);
  }
}

TEST_CASE("fluid multigrid: the coarsest level of a grid, and a grid that does not coarsen said with counts that do") {
  // (a 1021^2 cavity under multigrid CG ran 30 s and failed without a word of its grid: its only
  // level, a million cells, is smoothed, not solved)
  const auto coarsest = [](std::array<int64_t, 3> n, int dim) {
    return coarsest_level_cells(make_grid(dim, n, {0.1, 0.1, 0.1}, Boxes::kNeumann));
  };
  CHECK(coarsest({64, 64, 1}, 2) == 64);  // halved while above 64 cells
  CHECK(coarsest({96, 64, 1}, 2) == 24);  // 6 x 4
  CHECK(coarsest({1021, 1021, 1}, 2) == 1021 * 1021);
  CHECK(coarsest({6, 6, 6}, 3) == 27);  // 3 is odd
  CHECK(coarsening_note(make_grid(2, {1024, 1024, 1}, {0.1, 0.1, 0.1}, Boxes::kNeumann)).empty());
  CHECK(coarsening_note(make_grid(2, {131, 131, 1}, {0.1, 0.1, 0.1}, Boxes::kNeumann)).find("[132, 132]") !=
        std::string::npos);  // 33^2 at the coarsest
  // One factor for every axis, and a suggestion that does coarsen ([4096, 7] did not).
  CHECK(coarsening_note(make_grid(2, {4001, 7, 1}, {0.1, 0.1, 0.1}, Boxes::kNeumann)).find("[4002, 8]") !=
        std::string::npos);
  const std::string note = coarsening_note(make_grid(2, {1021, 1021, 1}, {0.1, 0.1, 0.1}, Boxes::kNeumann));
  CHECK(note.find("coarsest has 1042441 cells") != std::string::npos);
  CHECK(note.find("such as [1024, 1024]") != std::string::npos);
}
