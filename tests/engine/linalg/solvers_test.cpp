// The linear-algebra layer: CG (plain, Jacobi, preconditioned by a Cholesky factor) and the
// direct Cholesky solve against closed forms and against each other; failures as reports; the
// same bits on any number of threads.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "silt/linalg.hpp"
#include "support/scenes.hpp"

using namespace silt::linalg;
using silt::test::gaussian_vector;
using silt::test::rel_diff;

namespace {

SparseMatrix from_triplets(int64_t n, const std::vector<Eigen::Triplet<double>>& t) {
  SparseMatrix a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

// The 1D chain of N - 1 free points between two pinned ends: tridiag(-1, 2, -1), whose inverse
// is T^-1_ij = min(i,j) (N - max(i,j)) / N (1-based), Peyneau (2009) sec. 2.2.3's test.
SparseMatrix chain(int n_links) {
  const int n = n_links - 1;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  return from_triplets(n, t);
}

// A 2D grid Laplacian with a positive diagonal shift varying over orders of magnitude: symmetric
// positive definite and badly conditioned, like a resistance matrix with gaps of many sizes.
SparseMatrix grid(int side, unsigned seed, double perturb = 0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> t;
  auto id = [side](int i, int j) { return i * side + j; };
  std::vector<double> diag(n, 0.0);
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (auto [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (i + di >= side || j + dj >= side) continue;
        const double w = std::pow(10.0, 4 * u(rng)) * (1 + perturb * u(rng));  // 1 .. 1e4
        const int a = id(i, j), b = id(i + di, j + dj);
        t.emplace_back(a, b, -w);
        t.emplace_back(b, a, -w);
        diag[a] += w;
        diag[b] += w;
      }
  for (int k = 0; k < n; ++k) t.emplace_back(k, k, diag[k] + 1e-2);
  return from_triplets(n, t);
}

}  // namespace

TEST_CASE("every solver inverts the 1D chain to its closed form") {
  const int big_n = 200;
  const SparseMatrix t = chain(big_n);
  const SparseOperator op(t);
  CholeskyFactor f;
  REQUIRE(f.factorize(t).ok());
  for (int j : {1, 57, 199}) {
    CAPTURE(j);
    Vector e = Vector::Zero(big_n - 1);
    e[j - 1] = 1;
    Vector exact(big_n - 1);
    for (int i = 1; i < big_n; ++i) exact[i - 1] = std::min(i, j) * double(big_n - std::max(i, j)) / big_n;
    Vector x_cg = Vector::Zero(big_n - 1), x_direct;
    const SolveReport cg = conjugate_gradient(op, e, x_cg, {1e-13, 1000});
    CHECK(cg.ok());
    CHECK(cg.iterations <= big_n);  // CG is exact in at most n steps
    CHECK(rel_diff(x_cg, exact) < 1e-10);
    REQUIRE(f.solve(e, x_direct).ok());
    CHECK(rel_diff(x_direct, exact) < 1e-12);
  }
}

TEST_CASE("CG, Jacobi CG, factor-preconditioned CG and the direct solve agree") {
  const SparseMatrix a = grid(40, 1);
  const Vector b = gaussian_vector(a.rows(), 2);
  SolveOptions opt{1e-10, 20000};  // a relative residual round-off allows here (entries span 1e-2 .. 4e4)
  Vector x_cg = Vector::Zero(a.rows()), x_jac = x_cg, x_pcg = x_cg, x_direct;
  const SparseOperator op(a);
  const SolveReport cg = conjugate_gradient(op, b, x_cg, opt);
  const JacobiPreconditioner jacobi(a);
  const SolveReport jac = conjugate_gradient(op, b, x_jac, opt, &jacobi);
  CholeskyFactor f;
  REQUIRE(f.factorize(a).ok());
  const SolveReport pcg = conjugate_gradient(op, b, x_pcg, opt, &f);
  REQUIRE(f.solve(b, x_direct).ok());
  CHECK(cg.ok());
  CHECK(jac.ok());
  CHECK(pcg.ok());
  CHECK(cg.residual <= 1e-10);
  CHECK(jac.iterations < cg.iterations);  // the diagonal spans four decades
  CHECK(pcg.iterations <= 2);             // preconditioned by its own exact factor
  CHECK(rel_diff(x_cg, x_direct) < 1e-8);
  CHECK(rel_diff(x_jac, x_direct) < 1e-8);
  CHECK(rel_diff(x_pcg, x_direct) < 1e-10);
  CHECK(f.factor_entries() > a.nonZeros() / 2);
  CHECK(f.factor_bytes() >= 8 * f.factor_entries());
}

TEST_CASE("CG starts from zero when the guess is farther from the solution than zero") {
  // A paste's velocities solved under a viscosity 1e60 times lower, as the guess: CG cancelled its
  // residual to the guess's round-off, 1e55 times the solution (a box rate that took the box
  // through zero). From zero the solution is found to the tolerance.
  const SparseMatrix a = grid(20, 3) * 1e60;
  const Vector b = gaussian_vector(a.rows(), 5);
  CholeskyFactor f;
  REQUIRE(f.factorize(a).ok());
  Vector exact;
  REQUIRE(f.solve(b, exact).ok());
  Vector x = exact * 1e60;  // the solution of the matrix divided by 1e60
  const SolveReport rep = conjugate_gradient(SparseOperator(a), b, x, {1e-10, 20000}, &f);
  CHECK(rep.ok());
  CHECK(rel_diff(x, exact) < 1e-8);
  // A good guess is kept: CG from it takes no iteration.
  Vector y = exact;
  CHECK(conjugate_gradient(SparseOperator(a), b, y, {1e-8, 20000}, &f).iterations == 0);
}

TEST_CASE("an older factor preconditions a changed matrix and the solver refactorises when it no longer helps") {
  SolverSettings s;
  s.method = Method::kFactorPcg;
  s.options = {1e-10, 2000};
  s.refactor_iterations = 15;
  SpdSolver solver(s);
  Vector x = Vector::Zero(900);
  int64_t iterations = 0;
  // Matrices that drift a little each step (the same pattern), as a resistance matrix does.
  for (int step = 0; step < 12; ++step) {
    CAPTURE(step);
    const SparseMatrix a = grid(30, 7, 0.02 * step);
    const Vector b = gaussian_vector(a.rows(), 100 + step);
    const SolveReport r = solver.solve(a, b, x, false);
    REQUIRE(r.ok());
    iterations += r.iterations;
    Vector exact;
    CholeskyFactor f;
    REQUIRE(f.factorize(a).ok());
    REQUIRE(f.solve(b, exact).ok());
    CHECK(rel_diff(x, exact) < 1e-7);
  }
  CHECK(solver.analyses() == 1);  // the pattern never changed: one symbolic analysis
  CHECK(solver.refactorizations() < 12);
  CHECK(iterations < 12 * 40);
  // Direct and Jacobi CG through the same contract.
  for (Method m : {Method::kDirect, Method::kCg}) {
    s.method = m;
    SpdSolver other(s);
    const SparseMatrix a = grid(30, 7);
    const Vector b = gaussian_vector(a.rows(), 5);
    Vector y = Vector::Zero(a.rows());
    CHECK(other.solve(a, b, y, true).ok());
  }
}

TEST_CASE(
    "the iterations of a factor-preconditioned solve are bounded as a whole, the retry with a fresh factor included") {
  // The retry after a stale factor had the whole budget again: max_iterations = 1 gave solves of
  // 2 iterations that reported success.
  SolverSettings s;
  s.method = Method::kFactorPcg;
  s.options = {1e-10, 1};
  s.refactor_iterations = 15;
  SpdSolver solver(s);
  Vector x = Vector::Zero(900);
  const SparseMatrix a0 = grid(30, 7);
  REQUIRE(solver.solve(a0, gaussian_vector(a0.rows(), 1), x, false).ok());  // a fresh factor: exact
  const SparseMatrix a1 = grid(30, 7, 0.5);
  const SolveReport r = solver.solve(a1, gaussian_vector(a1.rows(), 2), x, false);
  CHECK_FALSE(r.ok());
  CHECK(r.status == SolveStatus::kMaxIterations);
  CHECK(r.iterations <= 1);
  CHECK(r.message.find("no convergence in 1 iterations") != std::string::npos);
}

TEST_CASE("a system that is not positive definite, or not finite, is a report, not a NaN") {
  SparseMatrix a = grid(10, 3);
  a.coeffRef(37, 37) = -5;  // an indefinite matrix
  CholeskyFactor f;
  const SolveReport r = f.factorize(a);
  CHECK(r.status == SolveStatus::kNotPositive);
  CHECK(r.message.find("column") != std::string::npos);
  CHECK_FALSE(f.ready());
  Vector x;
  CHECK(f.solve(gaussian_vector(100, 1), x).status == SolveStatus::kNotPositive);
  // CG along a direction of negative curvature.
  const SparseMatrix neg = -grid(10, 3);
  Vector y = Vector::Zero(100);
  const SolveReport c = conjugate_gradient(SparseOperator(neg), gaussian_vector(100, 2), y, {});
  CHECK(c.status == SolveStatus::kNotPositive);
  // Non-finite inputs.
  Vector b = gaussian_vector(100, 3);
  b[5] = std::nan("");
  const SparseMatrix good = grid(10, 3);
  Vector z = Vector::Zero(100);
  CHECK(conjugate_gradient(SparseOperator(good), b, z, {}).status == SolveStatus::kNotFinite);
  SparseMatrix inf = good;
  inf.coeffRef(3, 3) = INFINITY;
  CHECK(f.factorize(inf).status == SolveStatus::kNotFinite);
  // The iteration limit.
  Vector w = Vector::Zero(100);
  const SolveReport lim = conjugate_gradient(SparseOperator(good), gaussian_vector(100, 4), w, {1e-14, 3});
  CHECK(lim.status == SolveStatus::kMaxIterations);
  CHECK(lim.message.find("3 iterations") != std::string::npos);
  CHECK(std::isfinite(lim.residual));
}

TEST_CASE("the direct solve of a numerically singular matrix fails instead of returning its residual") {
  // The grid's Laplacian with a shift eps: a constant vector is its slowest direction, at eps.
  auto shifted = [](double eps) {
    SparseMatrix a = grid(12, 5);
    for (int k = 0; k < a.rows(); ++k) a.coeffRef(k, k) += eps - 1e-2;
    return a;
  };
  const Vector b = gaussian_vector(144, 7);
  SolverSettings settings;
  settings.method = Method::kDirect;
  settings.options.tolerance = 1e-10;
  // Condition near 1e6: solved to round-off.
  Vector x;
  const SolveReport fine = SpdSolver(settings).solve(shifted(1e-2), b, x, true);
  CHECK(fine.ok());
  CHECK(fine.residual < 1e-10);
  // Condition near 1e14: CHOLMOD's pivots stay positive, the residual does not reach 1e-10 (it
  // was returned as converged).
  Vector y;
  const SolveReport bad = SpdSolver(settings).solve(shifted(1e-10), b, y, true);
  CHECK(bad.status == SolveStatus::kMaxIterations);
  CHECK(bad.residual > 1e-10);
  CHECK(std::isfinite(bad.residual));
  CHECK(bad.message.find("numerically singular") != std::string::npos);
}

TEST_CASE("the direct solve refines its solution to a tolerance at round-off") {
  // One solve with the factor leaves a residual a few ulps above round-off (a paste with the
  // direct solver at lubrication.tolerance = 1e-15 failed at its third step at 1.05e-15); solves
  // of the residual's equation with the same factor take it lower: here from 3.5e-15 to 2.1e-15.
  SparseMatrix a = grid(12, 5);
  for (int k = 0; k < a.rows(); ++k) a.coeffRef(k, k) += 100;
  const Vector b = gaussian_vector(144, 7);
  CholeskyFactor once;
  REQUIRE(once.factorize(a).ok());
  Vector x1;
  REQUIRE(once.solve(b, x1).ok());
  CHECK((b - a * x1).norm() / b.norm() > 3e-15);
  SolverSettings settings;
  settings.method = Method::kDirect;
  settings.options.tolerance = 3e-15;
  Vector x;
  const SolveReport rep = SpdSolver(settings).solve(a, b, x, true);
  CHECK(rep.ok());
  CHECK(rep.residual <= 3e-15);
  CHECK((b - a * x).norm() / b.norm() == doctest::Approx(rep.residual).epsilon(1e-6));
}

TEST_CASE("a solve's error estimate is its preconditioned residual, of the error's size and direction") {
  // A factor of an older matrix (drifted by 30 %; and the same under a viscosity 1e6 times
  // higher, which preconditions as well) and Jacobi's diagonal, each solve stopped at a relative
  // residual of 1e-3. The preconditioned residual is taken the length along it that best cancels
  // the residual: with the factor, x + dx is closer to the solution than x, whatever its scale.
  const SparseMatrix old = grid(30, 7), a = grid(30, 7, 0.3);
  const Vector b = gaussian_vector(a.rows(), 11);
  Vector exact;
  CholeskyFactor f;
  REQUIRE(f.factorize(a).ok());
  REQUIRE(f.solve(b, exact).ok());
  for (const auto& each : {std::pair{Method::kFactorPcg, 1.0}, std::pair{Method::kFactorPcg, 1e6},
                           std::pair{Method::kFactorPcg, 1e-6}, std::pair{Method::kCg, 1.0}}) {
    const Method m = each.first;
    const double scale = each.second;
    const std::string name = method_name(m);
    CAPTURE(name);
    CAPTURE(scale);
    SolverSettings settings;
    settings.method = m;
    settings.options = {1e-3, 2000};
    settings.refactor_iterations = 1000;
    SpdSolver solver(settings);
    Vector x = Vector::Zero(a.rows()), dx;
    if (m == Method::kFactorPcg) {
      const SparseMatrix held = old * scale;
      REQUIRE(solver.restore_factor(held, 0).ok());
      solver.set_solves_since_factor(1);  // (stale: not refactorised before the solve)
    }
    const SolveReport r = solver.solve(a, b, x, false);
    REQUIRE(r.ok());
    REQUIRE(r.iterations > 0);
    solver.error_estimate(a, b, x, dx);
    const Vector residual = b - a * x;
    if (m == Method::kFactorPcg) {  // an approximate inverse: the error itself, roughly
      const Vector error = exact - x;
      CHECK(dx.norm() > 0.1 * error.norm());
      CHECK(dx.norm() < 10 * error.norm());
      CHECK((exact - x - dx).norm() < 0.9 * error.norm());
    } else {  // Jacobi's: the residual over the diagonal, at its best length
      const Vector jacobi = residual.cwiseQuotient(Vector(a.diagonal()));
      const Vector aj = a * jacobi;
      CHECK(rel_diff(dx, jacobi * (jacobi.dot(residual) / jacobi.dot(aj))) < 1e-6);
    }
    // The length: dx . (r - a dx) = 0.
    const Vector ad = a * dx;
    CHECK(std::abs(dx.dot(residual - ad)) < 1e-6 * std::abs(dx.dot(residual)));
    // Read from CG's last preconditioned residual, or made again (a solve that did not iterate,
    // started at its solution): of the same size.
    Vector again = x, dx_again;
    REQUIRE(solver.solve(a, b, again, false).iterations == 0);
    solver.error_estimate(a, b, again, dx_again);
    CHECK(rel_diff(dx_again, dx) < 0.5);
  }
  // A direct solve is refined to round-off: no estimate.
  SolverSettings direct;
  direct.method = Method::kDirect;
  SpdSolver solver(direct);
  Vector x = Vector::Zero(a.rows()), dx;
  REQUIRE(solver.solve(a, b, x, true).ok());
  solver.error_estimate(a, b, x, dx);
  CHECK(dx.size() == x.size());
  CHECK(dx.norm() == 0);
}

TEST_CASE("a right-hand side far below 1 is solved to the same bits, scaled (not read as zero)") {
  // A paste under a pressure of 1e-200: |b|^2 underflowed to 0, CG returned x = 0 as converged,
  // and the grains stood still with every stress reading 0.
  const SparseMatrix a = grid(20, 9);
  const Vector b = gaussian_vector(a.rows(), 10);
  const Vector tiny = b.unaryExpr([](double v) { return std::ldexp(v, -700); });  // about 1e-211
  for (Method m : {Method::kCg, Method::kFactorPcg, Method::kDirect}) {
    const std::string name = method_name(m);
    CAPTURE(name);
    SolverSettings settings;
    settings.method = m;
    Vector x = Vector::Zero(a.rows()), y = Vector::Zero(a.rows());
    REQUIRE(SpdSolver(settings).solve(a, b, x, true).ok());
    const SolveReport r = SpdSolver(settings).solve(a, tiny, y, true);
    REQUIRE(r.ok());
    CHECK(y.cwiseAbs().maxCoeff() > 0);  // (its norm would underflow)
    const Vector back = y.unaryExpr([](double v) { return std::ldexp(v, 700); });
    CHECK(std::memcmp(back.data(), x.data(), sizeof(double) * x.size()) == 0);
  }
}

TEST_CASE("CG that cannot go below round-off says it stagnated, and a diagonal entry of 0 is named") {
  // The grid's Laplacian shifted by 1e-10: condition near 1e14, so 1e-14 is out of reach.
  SparseMatrix a = grid(12, 5);
  for (int k = 0; k < a.rows(); ++k) a.coeffRef(k, k) += 1e-10 - 1e-2;
  Vector x = Vector::Zero(a.rows());
  const SolveReport r = conjugate_gradient(SparseOperator(a), gaussian_vector(a.rows(), 3), x, {1e-14, 100000});
  CHECK(r.status == SolveStatus::kStagnated);
  CHECK(r.iterations < 100000);  // not the limit
  CHECK(r.residual > 1e-14);
  CHECK(std::string(status_name(r.status)) == "stagnated");
  // Nothing resists unknown 17: Jacobi CG would divide by it; named, as a factorisation names its column.
  SparseMatrix z = grid(10, 3);
  for (SparseMatrix::InnerIterator it(z, 17); it; ++it) it.valueRef() = 0;
  for (int k = 0; k < z.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(z, k); it; ++it)
      if (it.row() == 17) it.valueRef() = 0;
  SolverSettings cg;
  cg.method = Method::kCg;
  Vector y = Vector::Zero(z.rows());
  const SolveReport c = SpdSolver(cg).solve(z, gaussian_vector(z.rows(), 4), y, true);
  CHECK(c.status == SolveStatus::kNotPositive);
  CHECK(c.column == 17);
}

TEST_CASE("a solve gives the same bits on 1, 2 and 4 threads") {
  const SparseMatrix a = grid(90, 11);  // 8,100 unknowns: more than one reduction block
  const Vector b = gaussian_vector(a.rows(), 12);
  auto solve_on = [&](int threads, Method m) {
    tbb::task_arena arena(threads);
    Vector x = Vector::Zero(a.rows());
    arena.execute([&] {
      SolverSettings s;
      s.method = m;
      s.options = {1e-8, 20000};
      SpdSolver solver(s);
      const SolveReport r = solver.solve(a, b, x, true);
      CAPTURE(r.message);
      REQUIRE(r.ok());
    });
    return x;
  };
  for (Method m : {Method::kCg, Method::kFactorPcg, Method::kDirect}) {
    const std::string method = method_name(m);
    CAPTURE(method);
    const Vector one = solve_on(1, m);
    for (int threads : {2, 4}) {
      const Vector other = solve_on(threads, m);
      CHECK(std::memcmp(one.data(), other.data(), sizeof(double) * one.size()) == 0);
    }
  }
}

namespace {

// A 3D grid Laplacian (side^3 unknowns) with weights spanning two decades (or `decades`) and a
// small shift: its factor has separators of side^2 columns, large enough to be shared among
// threads.
SparseMatrix grid_3d(int side, unsigned seed, double decades = 2, double shift = 1e-2) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = side * side * side;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> diag(n, shift);
  auto id = [side](int i, int j, int k) { return (k * side + j) * side + i; };
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        for (const auto& [di, dj, dk] : {std::array{1, 0, 0}, std::array{0, 1, 0}, std::array{0, 0, 1}}) {
          if (i + di >= side || j + dj >= side || k + dk >= side) continue;
          const double w = std::pow(10.0, decades * u(rng));
          const int a = id(i, j, k), b = id(i + di, j + dj, k + dk);
          t.emplace_back(a, b, -w);
          t.emplace_back(b, a, -w);
          diag[a] += w;
          diag[b] += w;
        }
  for (int k = 0; k < n; ++k) t.emplace_back(k, k, diag[k]);
  return from_triplets(n, t);
}

}  // namespace

TEST_CASE("silt's supernodal solves agree with CHOLMOD's and give the same bits on 1, 2 and 4 threads") {
  const SparseMatrix a = grid_3d(22, 5);  // 10,648 unknowns, top separators of about 484 columns
  const Vector b = gaussian_vector(a.rows(), 6);
  CholeskyFactor f;
  REQUIRE(f.factorize(a).ok());
  const SolveSplit split = f.solve_split();
  CHECK(split.tasks > 2);     // the subtrees below the top separators run as parallel tasks
  CHECK(split.shared > 0.1);  // and the largest separators are shared by blocks
  CHECK(split.in_tasks + split.shared <= 1.0);
  Vector reference;
  f.use_cholmod_solve(true);
  REQUIRE(f.solve(b, reference).ok());
  f.use_cholmod_solve(false);
  auto solve_on = [&](int threads) {
    tbb::task_arena arena(threads);
    Vector x;
    arena.execute([&] { REQUIRE(f.solve(b, x).ok()); });
    return x;
  };
  const Vector one = solve_on(1);
  // Both are backward stable: their residuals are at round-off, and they differ by round-off
  // times the condition number (about 1e5 here).
  CHECK((b - a * one).norm() / b.norm() < 1e-13);
  CHECK((b - a * reference).norm() / b.norm() < 1e-13);
  CHECK(rel_diff(one, reference) < 1e-10);
  for (int threads : {2, 4}) {
    const Vector other = solve_on(threads);
    CHECK(std::memcmp(one.data(), other.data(), sizeof(double) * one.size()) == 0);
  }
}

// A 3D grid Laplacian and, after its unknowns, blocks of three coupled to nothing else (random
// symmetric positive definite 3 x 3: a grain's rotation in a factor that keeps only the rotations'
// own blocks), each alone in the elimination tree.
TEST_CASE("supernodes alone in their trees are solved apart, exactly, with the same bits on 1, 2 and 4 threads") {
  const SparseMatrix g = grid_3d(22, 5);
  const int64_t n0 = g.rows(), blocks = 2000, n = n0 + 3 * blocks;
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < g.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(g, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Matrix3d> own(blocks);
  for (int64_t b = 0; b < blocks; ++b) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = u(rng);
    own[b] = m * m.transpose() + std::pow(10.0, 3 * u(rng)) * Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t.emplace_back(n0 + 3 * b + i, n0 + 3 * b + j, own[b](i, j));
  }
  const SparseMatrix a = from_triplets(n, t);
  const Vector rhs = gaussian_vector(n, 7);
  CholeskyFactor f;
  REQUIRE(f.factorize(a).ok());
  const SolveSplit split = f.solve_split();
  CHECK(split.alone == blocks);
  CHECK(split.tasks > 2);  // the grid's subtrees as before
  CHECK(split.in_tasks + split.shared <= 1.0);
  Vector reference;
  f.use_cholmod_solve(true);
  REQUIRE(f.solve(rhs, reference).ok());
  f.use_cholmod_solve(false);
  for (bool single : {false, true}) {
    CAPTURE(single);
    f.set_single_preconditioner(single);
    auto on = [&](int threads) {
      tbb::task_arena arena(threads);
      Vector x;
      arena.execute([&] {
        if (single) f.apply(rhs, x);
        else REQUIRE(f.solve(rhs, x).ok());
      });
      return x;
    };
    const Vector one = on(1);
    // Each block's solution against Eigen's: a 3 x 3 system of condition at most about 1e4, to
    // round-off in double; in single precision to the rounding of the factor (2^-24) times that.
    double worst = 0;
    for (int64_t b = 0; b < blocks; ++b) {
      const Eigen::Vector3d want = own[b].llt().solve(rhs.segment<3>(n0 + 3 * b));
      worst = std::max(worst, (one.segment<3>(n0 + 3 * b) - want).norm() / want.norm());
    }
    CHECK(worst < (single ? 1e-4 : 1e-12));
    CHECK(rel_diff(one.head(n0), reference.head(n0)) < (single ? 1e-5 : 1e-10));
    for (int threads : {2, 4}) {
      const Vector other = on(threads);
      CHECK(std::memcmp(one.data(), other.data(), sizeof(double) * one.size()) == 0);
    }
  }
}

TEST_CASE("a factor applied in single precision preconditions as well, with the same bits on 1, 2 and 4 threads") {
  const SparseMatrix a = grid_3d(22, 5);
  const Vector b = gaussian_vector(a.rows(), 6);
  CholeskyFactor f;
  REQUIRE(f.factorize(a).ok());
  CHECK_FALSE(f.applies_single());
  const int64_t bytes = f.factor_bytes();
  f.set_single_preconditioner(true);  // the factor held is rounded at once
  REQUIRE(f.applies_single());
  CHECK(f.factor_bytes() == bytes + 4 * f.factor_entries());
  Vector exact;
  REQUIRE(f.solve(b, exact).ok());  // solve() stays exact
  CHECK((b - a * exact).norm() / b.norm() < 1e-13);
  auto apply_on = [&](int threads) {
    tbb::task_arena arena(threads);
    Vector z;
    arena.execute([&] { f.apply(b, z); });
    return z;
  };
  const Vector one = apply_on(1);
  // The rounded factor L~ = L + E, |E| <= 2^-24 |L|: L~ L~^T differs from A by about 2^-23 |A|,
  // and its solve from A^-1 b by at most that times the condition number (about 1e5 here; the
  // errors of the entries do not add up so, and 5.6e-8 is measured). 1e-5 catches a value out
  // of place or rounded to fewer bits.
  const double err = rel_diff(one, exact);
  CHECK(err > 0);  // the floats were used
  CHECK(err < 1e-5);
  for (int threads : {2, 4}) {
    const Vector other = apply_on(threads);
    CHECK(std::memcmp(one.data(), other.data(), sizeof(double) * one.size()) == 0);
  }
  // As CG's preconditioner: the exact solution to 1e-12 in a few iterations.
  const SparseOperator op(a);
  Vector x = Vector::Zero(a.rows());
  const SolveReport r = conjugate_gradient(op, b, x, SolveOptions{1e-12, 100}, &f);
  CHECK(r.ok());
  CHECK(r.iterations <= 3);  // 2 measured
  CHECK(rel_diff(x, exact) < 1e-9);
  // Set back, the factor is applied exactly again.
  f.set_single_preconditioner(false);
  CHECK_FALSE(f.applies_single());
  const Vector z = apply_on(1);
  CHECK(std::memcmp(z.data(), exact.data(), sizeof(double) * z.size()) == 0);
}

TEST_CASE("a factor whose values a float cannot hold is applied in double precision") {
  SparseMatrix a = grid_3d(8, 3);
  a *= 1e80;  // the diagonal of L about 1e40: beyond the largest float
  const Vector b = gaussian_vector(a.rows(), 4);
  CholeskyFactor f;
  f.set_single_preconditioner(true);
  REQUIRE(f.factorize(a).ok());
  CHECK_FALSE(f.applies_single());
  Vector exact, z;
  REQUIRE(f.solve(b, exact).ok());
  f.apply(b, z);
  CHECK(std::memcmp(exact.data(), z.data(), sizeof(double) * z.size()) == 0);
  a *= 1e-150;  // the diagonal about 1e-35: rounded to floats, its small entries would lose bits
  REQUIRE(f.factorize(a).ok());
  CHECK_FALSE(f.applies_single());
}

TEST_CASE("a solve that a factor in single precision leaves short goes on in double") {
  // A 3D grid whose weights span seven decades (a diagonal shift of 1e-3): to 1e-7 a fresh factor
  // solves it in 1 iteration, rounded to floats in 3.
  const SparseMatrix a = grid_3d(16, 3, 7, 1e-3);
  const int64_t n = a.rows();
  const Vector b = gaussian_vector(n, 6);
  auto solve_with = [&](bool single, int threshold, int64_t& retries) {
    SolverSettings s;
    s.options = {1e-7, 10};
    s.refactor_iterations = threshold;
    s.single_factor = single;
    SpdSolver solver(s);
    Vector x = Vector::Zero(n);
    const SolveReport r = solver.solve(a, b, x, true);
    retries = solver.double_retries();
    CHECK(solver.factor().applies_single() == single);  // its floats kept through the retry
    return r;
  };
  int64_t retries = -1;
  SolveReport r = solve_with(false, 2, retries);
  CHECK(r.ok());
  CHECK(r.iterations == 1);
  r = solve_with(true, 5, retries);  // within the threshold: floats throughout
  CHECK(r.ok());
  CHECK(r.iterations == 3);
  CHECK(retries == 0);
  r = solve_with(true, 2, retries);  // past it: 2 iterations with the floats, then the double factor
  CHECK(r.ok());
  CHECK(r.iterations == 3);
  CHECK(retries == 1);
  CHECK(r.residual <= 1e-7);
}
