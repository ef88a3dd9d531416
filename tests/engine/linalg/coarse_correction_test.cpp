// The balancing preconditioner: a factor of an older matrix, corrected exactly on the directions
// of its stiff entries that have turned since, as a paste's contacts turn as the grains roll.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "linalg/vector_ops.hpp"
#include "silt/linalg.hpp"
#include "support/scenes.hpp"

using namespace silt::linalg;
using silt::test::gaussian_vector;
using silt::test::rel_diff;

namespace {

// Points of a side x side grid, two translations each, joined to their right and upper
// neighbours by a resistance k_n along a direction n of the link (at an angle of its own) and 1
// across it, on the relative motion; a fifth of the links are stiff (k_n = 1e6), the others
// 1 to 10; each point is held to the liquid by 1. `turn` rotates every link's direction by that
// angle: the same system a step later.
struct Links {
  int side = 0;
  std::vector<int> a, b;
  std::vector<double> angle, k_n;
};

Links make_links(int side, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Links l;
  l.side = side;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (auto [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (i + di >= side || j + dj >= side) continue;
        l.a.push_back(i * side + j);
        l.b.push_back((i + di) * side + j + dj);
        l.angle.push_back(2 * std::numbers::pi * u(rng));
        l.k_n.push_back(u(rng) < 0.2 ? 1e6 : 1 + 9 * u(rng));
      }
  return l;
}

SparseMatrix matrix(const Links& l, double turn) {
  std::vector<Eigen::Triplet<double>> t;
  const int n = 2 * l.side * l.side;
  for (size_t e = 0; e < l.a.size(); ++e) {
    const double c = std::cos(l.angle[e] + turn), s = std::sin(l.angle[e] + turn);
    const double nv[2] = {c, s}, tv[2] = {-s, c};
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q) {
        const double v = l.k_n[e] * nv[p] * nv[q] + tv[p] * tv[q];
        t.emplace_back(2 * l.a[e] + p, 2 * l.a[e] + q, v);
        t.emplace_back(2 * l.b[e] + p, 2 * l.b[e] + q, v);
        t.emplace_back(2 * l.a[e] + p, 2 * l.b[e] + q, -v);
        t.emplace_back(2 * l.b[e] + p, 2 * l.a[e] + q, -v);
      }
  }
  for (int k = 0; k < n; ++k) t.emplace_back(k, k, 1.0);
  SparseMatrix m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  m.makeCompressed();
  return m;
}

// One column per stiff link, its direction (turned) on the relative motion; `twice` repeats
// every column (dependent columns).
SparseMatrix stiff_directions(const Links& l, double turn, bool twice = false) {
  std::vector<Eigen::Triplet<double>> t;
  int col = 0;
  for (size_t e = 0; e < l.a.size(); ++e) {
    if (l.k_n[e] < 1e3) continue;
    for (int copy = 0; copy < (twice ? 2 : 1); ++copy, ++col) {
      const double nv[2] = {std::cos(l.angle[e] + turn), std::sin(l.angle[e] + turn)};
      for (int p = 0; p < 2; ++p) {
        t.emplace_back(2 * l.a[e] + p, col, nv[p]);
        t.emplace_back(2 * l.b[e] + p, col, -nv[p]);
      }
    }
  }
  SparseMatrix w(2 * l.side * l.side, col);
  w.setFromTriplets(t.begin(), t.end());
  return w;
}

}  // namespace

TEST_CASE("a coarse correction on the turned stiff directions keeps an old factor good") {
  const Links l = make_links(24, 3);
  const SparseMatrix a0 = matrix(l, 0), a1 = matrix(l, 0.01);
  const Vector b = gaussian_vector(a1.rows(), 4);
  const SparseOperator op(a1);
  const SolveOptions opt{1e-8, 5000};
  CholeskyFactor old;
  REQUIRE(old.factorize(a0).ok());
  Vector exact;
  {
    CholeskyFactor f;
    REQUIRE(f.factorize(a1).ok());
    REQUIRE(f.solve(b, exact).ok());
  }
  // The old factor alone: a turn of 0.01 changes a stiff link by 1e4 across it, 1e4 times its
  // resistance there.
  Vector x_old = Vector::Zero(a1.rows());
  const SolveReport r_old = conjugate_gradient(op, b, x_old, opt, &old);
  CoarseCorrection cc;
  const SparseMatrix w = stiff_directions(l, 0.01);
  REQUIRE(w.cols() > 150);
  SparseMatrix taken = w;  // setup takes its W
  REQUIRE(cc.setup(a1, taken, old).ok());
  CHECK(cc.ready());
  CHECK(cc.columns() == w.cols());
  Vector x_cc = Vector::Zero(a1.rows());
  const SolveReport r_cc = conjugate_gradient(op, b, x_cc, opt, &cc);
  CAPTURE(r_old.iterations);
  CAPTURE(r_cc.iterations);
  CHECK(r_cc.ok());
  CHECK(r_cc.iterations <= 12);
  CHECK(r_old.iterations > 4 * r_cc.iterations);
  CHECK(rel_diff(x_cc, exact) < 1e-6);

  // Symmetric (u . P v = v . P u), as PCG needs.
  const Vector u = gaussian_vector(a1.rows(), 5), v = gaussian_vector(a1.rows(), 6);
  Vector pu, pv;
  cc.apply(u, pu);
  cc.apply(v, pv);
  CHECK(std::abs(u.dot(pv) - v.dot(pu)) <= 1e-9 * std::abs(u.dot(pv)));
  CHECK(u.dot(pu) > 0);

  // Every column twice (a self-stressed cluster of contacts makes W's columns dependent): E is
  // held definite, and the solve converges as well.
  CoarseCorrection twice;
  SparseMatrix doubled = stiff_directions(l, 0.01, true);
  REQUIRE(twice.setup(a1, doubled, old).ok());
  Vector x_tw = Vector::Zero(a1.rows());
  const SolveReport r_tw = conjugate_gradient(op, b, x_tw, opt, &twice);
  CAPTURE(r_tw.iterations);
  CHECK(r_tw.ok());
  CHECK(r_tw.iterations <= r_cc.iterations + 3);
  CHECK(rel_diff(x_tw, exact) < 1e-6);

  // No columns: the factor alone, the same bits.
  CoarseCorrection none;
  SparseMatrix empty(a1.rows(), 0);
  CHECK(none.setup(a1, empty, old).ok());
  CHECK_FALSE(none.ready());
  Vector z_none, z_old;
  none.apply(b, z_none);
  old.apply(b, z_old);
  CHECK(z_none == z_old);
}

TEST_CASE("the solver corrects its factor on the caller's coarse space") {
  const Links l = make_links(20, 9);
  SolverSettings s;
  s.options = {1e-8, 5000};
  s.refactor_iterations = 15;
  int64_t its[2] = {0, 0}, factors[2] = {0, 0};
  for (int with = 0; with < 2; ++with) {
    SpdSolver solver(s);
    Vector x = Vector::Zero(2 * 20 * 20);
    double turn = 0;
    for (int step = 0; step < 8; ++step) {
      CAPTURE(step);
      turn += 0.003;  // the stiff links turn a little more each step
      const SparseMatrix a = matrix(l, turn);
      if (with) solver.coarse_space = [&l, turn] { return stiff_directions(l, turn); };
      const Vector b = gaussian_vector(a.rows(), 20 + step);
      const SolveReport r = solver.solve(a, b, x, false);
      REQUIRE(r.ok());
      its[with] += r.iterations;
      CHECK(solver.coarse_columns() == (with ? stiff_directions(l, turn).cols() : 0));
    }
    factors[with] = solver.refactorizations();
  }
  CAPTURE(its[0]);
  CAPTURE(its[1]);
  CHECK(factors[1] == 1);  // one factor serves every step
  CHECK(factors[0] > 2);
  CHECK(its[1] < its[0]);
}

namespace {

// The stiff links' columns with a key each (the link's index), leaving out those whose index is
// in `skip`.
CoarseSpace keyed_directions(const Links& l, double turn, const std::vector<int>& skip) {
  std::vector<Eigen::Triplet<double>> t;
  std::vector<int64_t> keys;
  for (size_t e = 0; e < l.a.size(); ++e) {
    if (l.k_n[e] < 1e3 || std::find(skip.begin(), skip.end(), static_cast<int>(e)) != skip.end()) continue;
    const int col = static_cast<int>(keys.size());
    const double nv[2] = {std::cos(l.angle[e] + turn), std::sin(l.angle[e] + turn)};
    for (int p = 0; p < 2; ++p) {
      t.emplace_back(2 * l.a[e] + p, col, nv[p]);
      t.emplace_back(2 * l.b[e] + p, col, -nv[p]);
    }
    keys.push_back(static_cast<int64_t>(e));
  }
  CoarseSpace space({}, std::move(keys));
  space.w.resize(2 * l.side * l.side, static_cast<int>(space.keys.size()));
  space.w.setFromTriplets(t.begin(), t.end());
  return space;
}

std::vector<int> stiff_links(const Links& l) {
  std::vector<int> s;
  for (size_t e = 0; e < l.a.size(); ++e)
    if (l.k_n[e] >= 1e3) s.push_back(static_cast<int>(e));
  return s;
}

}  // namespace

TEST_CASE("E is ordered from the last setup's order while its columns are mostly the same") {
  const Links l = make_links(24, 3);
  const std::vector<int> stiff = stiff_links(l);
  REQUIRE(stiff.size() > 100);
  CholeskyFactor old;
  REQUIRE(old.factorize(matrix(l, 0)).ok());
  const SolveOptions opt{1e-8, 5000};

  // Step 0 leaves out three stiff links; step 1 takes them in (new columns) and leaves out two
  // others, as contacts are made and broken.
  const std::vector<int> skip0 = {stiff[3], stiff[40], stiff[90]}, skip1 = {stiff[10], stiff[70]};
  CoarseCorrection cc;
  CoarseSpace s0 = keyed_directions(l, 0.005, skip0);
  REQUIRE(cc.setup(matrix(l, 0.005), s0.w, old, &s0.keys).ok());
  CHECK(cc.fresh_orderings() == 1);
  CHECK(cc.kept_orderings() == 0);
  // The memory: the columns' keys in the order E was eliminated, a permutation of them.
  const CoarseCorrection::OrderMemory after0 = cc.order_memory();
  std::vector<int64_t> sorted = after0.keys;
  std::sort(sorted.begin(), sorted.end());
  CHECK(sorted == s0.keys);
  CHECK(after0.fill >= 1);

  const SparseMatrix a1 = matrix(l, 0.01);
  CoarseSpace s1 = keyed_directions(l, 0.01, skip1);
  const std::vector<int64_t> keys1 = s1.keys;
  CoarseSpace s1_copy = s1;
  REQUIRE(cc.setup(a1, s1.w, old, &s1.keys).ok());
  CHECK(cc.fresh_orderings() == 1);
  CHECK(cc.kept_orderings() == 1);  // the kept order fills E's factor in within the slack
  const Vector b = gaussian_vector(a1.rows(), 7);
  Vector exact;
  {
    CholeskyFactor f;
    REQUIRE(f.factorize(a1).ok());
    REQUIRE(f.solve(b, exact).ok());
  }
  Vector x = Vector::Zero(a1.rows());
  const SolveReport r = conjugate_gradient(SparseOperator(a1), b, x, opt, &cc);
  CAPTURE(r.iterations);
  CHECK(r.ok());
  CHECK(r.iterations <= 12);
  CHECK(rel_diff(x, exact) < 1e-6);

  // A sequence restored from the memory of step 0 orders E, and so preconditions, to the bit.
  CoarseCorrection restored;
  restored.set_order_memory(after0);
  REQUIRE(restored.setup(a1, s1_copy.w, old, &keys1).ok());
  CHECK(restored.kept_orderings() == 1);
  CHECK(restored.order_memory().keys == cc.order_memory().keys);
  Vector z_cc, z_restored;
  cc.apply(b, z_cc);
  restored.apply(b, z_restored);
  CHECK(z_cc == z_restored);

  // Given another memory (a state restored or replayed), E is analysed from it even for the
  // pattern it holds; given its own, not.
  CoarseSpace again = keyed_directions(l, 0.01, skip1);
  cc.set_order_memory(cc.order_memory());
  REQUIRE(cc.setup(a1, again.w, old, &again.keys).ok());
  CHECK(cc.kept_orderings() + cc.fresh_orderings() == 2);
  again = keyed_directions(l, 0.01, skip1);
  cc.set_order_memory(after0);
  REQUIRE(cc.setup(a1, again.w, old, &again.keys).ok());
  CHECK(cc.kept_orderings() == 2);
  Vector z_again;
  cc.apply(b, z_again);
  CHECK(z_again == z_restored);

  // Mostly new columns (other keys): a fresh ordering.
  CoarseSpace s2 = keyed_directions(l, 0.01, {});
  for (int64_t& k : s2.keys) k += 100000;
  REQUIRE(cc.setup(a1, s2.w, old, &s2.keys).ok());
  CHECK(cc.fresh_orderings() == 2);
  CHECK(cc.kept_orderings() == 2);
}

TEST_CASE("E's weak couplings dropped onto its diagonal: the correction stays definite, and nearly exact") {
  // Two stiff links couple in E by about 1e6 through a point they share, and by 1 to 10 through
  // a soft link between their points: the couplings a drop of 1e-4 removes.
  const Links l = make_links(24, 3);
  const SparseMatrix a0 = matrix(l, 0), a1 = matrix(l, 0.01);
  CholeskyFactor old;
  REQUIRE(old.factorize(a0).ok());
  const Vector b = gaussian_vector(a1.rows(), 4);
  Vector exact;
  {
    CholeskyFactor f;
    REQUIRE(f.factorize(a1).ok());
    REQUIRE(f.solve(b, exact).ok());
  }
  const SolveOptions opt{1e-8, 5000};
  int its_exact = 0;
  int64_t bytes_exact = 0;
  for (double drop : {0.0, 1e-4, 1e-2, 1.0}) {
    CAPTURE(drop);
    CoarseCorrection cc;
    cc.set_drop(drop);
    SparseMatrix w = stiff_directions(l, 0.01);
    REQUIRE(cc.setup(a1, w, old).ok());
    Vector x = Vector::Zero(a1.rows());
    const SolveReport r = conjugate_gradient(SparseOperator(a1), b, x, opt, &cc);
    CAPTURE(r.iterations);
    CHECK(r.ok());
    CHECK(rel_diff(x, exact) < 1e-6);
    // Symmetric and positive, whatever the drop.
    for (unsigned seed : {5u, 6u, 7u}) {
      const Vector u = gaussian_vector(a1.rows(), seed), v = gaussian_vector(a1.rows(), seed + 10);
      Vector pu, pv;
      cc.apply(u, pu);
      cc.apply(v, pv);
      CHECK(std::abs(u.dot(pv) - v.dot(pu)) <= 1e-9 * std::abs(u.dot(pv)));
      CHECK(u.dot(pu) > 0);
    }
    if (drop == 0) {
      its_exact = r.iterations;
      bytes_exact = cc.bytes();
    } else if (drop == 1e-4) {
      CHECK(r.iterations <= its_exact + 1);
      CHECK(cc.bytes() < bytes_exact);  // a smaller factor of E
    }
  }
}

TEST_CASE("the coarse correction's products on several threads give Eigen's bits") {
  const Links l = make_links(40, 5);
  const SparseMatrix a = matrix(l, 0.02), w = stiff_directions(l, 0.02);
  const SparseMatrix wt = w.transpose();
  const Vector x = gaussian_vector(a.rows(), 3);
  SparseMatrix aw_eigen = a * w;
  aw_eigen.makeCompressed();
  SparseMatrix e_eigen = wt * aw_eigen;
  e_eigen.makeCompressed();
  const Vector wx_eigen = w.transpose() * x;
  auto same = [](const SparseMatrix& p, const SparseMatrix& q) {
    return p.rows() == q.rows() && p.cols() == q.cols() && p.nonZeros() == q.nonZeros() &&
           std::equal(p.outerIndexPtr(), p.outerIndexPtr() + p.cols() + 1, q.outerIndexPtr()) &&
           std::equal(p.innerIndexPtr(), p.innerIndexPtr() + p.nonZeros(), q.innerIndexPtr()) &&
           std::memcmp(p.valuePtr(), q.valuePtr(), sizeof(double) * static_cast<size_t>(p.nonZeros())) == 0;
  };
  for (int threads : {1, 2, 4}) {
    CAPTURE(threads);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      const SparseMatrix aw = sparse_product(a, w);
      CHECK(same(aw, aw_eigen));
      CHECK(same(sparse_product(wt, aw), e_eigen));
      Vector wx;
      transpose_times(w, x, wx);
      CHECK(std::memcmp(wx.data(), wx_eigen.data(), sizeof(double) * static_cast<size_t>(wx.size())) == 0);
    });
  }
}
