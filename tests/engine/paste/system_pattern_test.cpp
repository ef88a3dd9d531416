// The resistance system's sparse pattern, written column by column, against the pattern of the
// triplets it stands for (every local pair of unknowns of every connection, and every diagonal
// entry), and its assembled values (and the shear's right-hand side) against the sums of the
// connections' local blocks in their order, to the bit and on one thread as on several: random
// connection graphs in 2D and 3D with grains left out, with and without box strain rates.
#include <doctest/doctest.h>

#include <tbb/task_arena.h>
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "paste/system.hpp"

using namespace silt;
using namespace silt::paste;

namespace {

// `count` connections between `grains` grains, the last three grains never connected; the same
// pair at most once, as in a pair list.
std::vector<Connection> pattern_test_graph(int dim, int64_t grains, int count, std::mt19937_64& rng) {
  std::uniform_int_distribution<int32_t> pick(0, static_cast<int32_t>(grains - 4));
  std::normal_distribution<double> g;
  std::set<std::pair<int32_t, int32_t>> seen;
  std::vector<Connection> cs;
  while (static_cast<int>(cs.size()) < count) {
    Connection c;
    c.i = pick(rng);
    c.j = pick(rng);
    if (c.i == c.j || !seen.insert({std::min(c.i, c.j), std::max(c.i, c.j)}).second) continue;
    double norm = 0;
    for (int a = 0; a < dim; ++a) {
      c.n[a] = g(rng);
      norm += c.n[a] * c.n[a];
    }
    for (int a = 0; a < dim; ++a) {
      c.n[a] /= std::sqrt(norm);
      c.r[a] = 1.05 * c.n[a];
    }
    c.xi_n = 1.0 + std::abs(g(rng));
    c.xi_t = 0.1 + 0.1 * std::abs(g(rng));
    cs.push_back(c);
  }
  return cs;
}

// The same matrix from triplets: the local blocks summed by Eigen.
linalg::SparseMatrix pattern_from_triplets(const SystemLayout& l, const std::vector<Connection>& cs,
                                           const std::vector<double>& radius) {
  const int n = local_size(l);
  std::vector<Eigen::Triplet<double>> t;
  for (int64_t k = 0; k < l.size(); ++k) t.emplace_back(static_cast<int>(k), static_cast<int>(k), 0.0);
  std::vector<double> loc(static_cast<size_t>(n * n));
  for (const Connection& c : cs) {
    local_block(l, c, radius[c.i], radius[c.j], c.xi_n, c.xi_t, loc.data());
    for (int q = 0; q < n; ++q)
      for (int r = 0; r < n; ++r) {
        const int64_t gq = local_to_global(l, c, q), gr = local_to_global(l, c, r);
        if (gq >= 0 && gr >= 0) t.emplace_back(static_cast<int>(gr), static_cast<int>(gq), loc[r * n + q]);
      }
  }
  linalg::SparseMatrix a(l.size(), l.size());
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

// The shear's right-hand side, -shear_rate times each local block's shear column, summed in the
// connections' order.
linalg::Vector shear_rhs_in_order(const SystemLayout& l, const std::vector<Connection>& cs,
                                  const std::vector<double>& radius, double shear_rate) {
  const int n = local_size(l);
  linalg::Vector rhs = linalg::Vector::Zero(l.size());
  if (!l.shear) return rhs;
  std::vector<double> loc(static_cast<size_t>(n * n));
  for (const Connection& c : cs) {
    local_block(l, c, radius[c.i], radius[c.j], c.xi_n, c.xi_t, loc.data());
    for (int r = 0; r < n - 1; ++r) rhs[local_to_global(l, c, r)] -= loc[r * n + (n - 1)] * shear_rate;
  }
  return rhs;
}

// The unknowns of `grains` grains with the first `boxes` box lengths controlled.
SystemLayout test_layout(int dim, int64_t grains, int boxes, bool shear) {
  bool controlled[3] = {false, false, false};
  for (int a = 0; a < boxes; ++a) controlled[a] = true;
  return make_layout(dim, grains, controlled, shear);
}

std::vector<double> test_radii(int64_t grains, std::mt19937_64& rng) {
  std::vector<double> radius(static_cast<size_t>(grains));
  for (auto& r : radius) r = 0.4 + 0.1 * std::uniform_real_distribution<double>()(rng);
  return radius;
}

}  // namespace

TEST_CASE("paste: the resistance pattern written by columns is the triplets' pattern, its values their sums") {
  std::mt19937_64 rng(11);
  for (int dim : {2, 3})
    for (int boxes = 0; boxes <= dim; ++boxes)
      for (bool shear : {false, true}) {
        CAPTURE(dim);
        CAPTURE(boxes);
        CAPTURE(shear);
        // 40 grains, and enough for the assembly to be shared among threads.
        for (int64_t grains : {40, 600}) {
          const SystemLayout l = test_layout(dim, grains, boxes, shear);
          const std::vector<double> radius = test_radii(grains, rng);
          ResistanceSystem sys;
          // Several graphs in turn (the pattern rebuilt each time), the empty one included.
          for (int count : {0, 1, 30, 80, 30}) {
            CAPTURE(count);
            const std::vector<Connection> cs =
                pattern_test_graph(dim, grains, count * static_cast<int>(grains / 40), rng);
            CHECK(sys.assemble(l, cs, radius, 0.3));
            const linalg::SparseMatrix want = pattern_from_triplets(l, cs, radius);
            const linalg::SparseMatrix& got = sys.matrix();
            REQUIRE(got.nonZeros() == want.nonZeros());
            CHECK(std::equal(got.outerIndexPtr(), got.outerIndexPtr() + l.size() + 1, want.outerIndexPtr()));
            CHECK(std::equal(got.innerIndexPtr(), got.innerIndexPtr() + got.nonZeros(), want.innerIndexPtr()));
            // The same bits: each entry takes its connections' additions in their order, as the
            // triplets' sums do, whatever the threads (the assembly runs grain by grain).
            CHECK(std::equal(got.valuePtr(), got.valuePtr() + got.nonZeros(), want.valuePtr()));
            const linalg::Vector want_rhs = shear_rhs_in_order(l, cs, radius, 0.3);
            CHECK(std::equal(sys.shear_rhs().data(), sys.shear_rhs().data() + l.size(), want_rhs.data()));
            ResistanceSystem one;
            tbb::task_arena(1).execute([&] { one.assemble(l, cs, radius, 0.3); });
            CHECK(std::equal(got.valuePtr(), got.valuePtr() + got.nonZeros(), one.matrix().valuePtr()));
            for (int64_t k = 0; k < l.size(); ++k) CHECK(got.innerIndexPtr()[sys.diagonal_position(k)] == k);
            // The same connections again: the pattern is kept.
            CHECK_FALSE(sys.assemble(l, cs, radius, 0.3));
          }
        }
      }
}

TEST_CASE(
    "paste: the factor's matrix with each grain's own rotation block keeps Xi's other entries, "
    "drops every coupling of a rotation, and its spectrum lies within Xi's") {
  std::mt19937_64 rng(23);
  struct Case {
    int dim, boxes;
    bool shear;
  };
  for (const Case& variant : {Case{2, 0, false}, Case{2, 2, true}, Case{3, 0, false}, Case{3, 0, true},
                              Case{3, 3, false}, Case{3, 3, true}}) {
    const int dim = variant.dim, boxes = variant.boxes;
    const bool shear = variant.shear;
    INFO("dim " << dim << ", " << boxes << " box strain rates, shear " << shear);
    const int64_t grains = 24;
    const SystemLayout l = test_layout(dim, grains, boxes, shear);
    const std::vector<double> radius = test_radii(grains, rng);
    ResistanceSystem sys;
    const std::vector<Connection> cs = pattern_test_graph(dim, grains, 50, rng);
    sys.assemble(l, cs, radius, 0.3);
    // Definite, as a pinned or dragged Xi is: the identity added.
    for (int64_t k = 0; k < l.size(); ++k) sys.matrix().valuePtr()[sys.diagonal_position(k)] += 1.0;
    const Eigen::MatrixXd a(sys.matrix());
    const Eigen::MatrixXd m(sys.sparsified(std::vector<uint8_t>(cs.size(), 1), true));
    const int p = l.per_grain;
    auto rotation = [&](int64_t k) { return k < grains * p && k % p >= dim; };
    int kept = 0, dropped = 0;
    for (int64_t r = 0; r < l.size(); ++r)
      for (int64_t c = 0; c < l.size(); ++c) {
        const bool coupling = (rotation(r) || rotation(c)) && !(rotation(r) && rotation(c) && r / p == c / p);
        if (coupling) {
          CHECK(m(r, c) == 0);
          dropped += a(r, c) != 0;
        } else {
          CHECK(m(r, c) == a(r, c));
          kept += a(r, c) != 0;
        }
      }
    CHECK(kept > 0);
    CHECK(dropped > 0);
    // Principal submatrices of a symmetric matrix have their eigenvalues within its range.
    const Eigen::VectorXd ea = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a).eigenvalues();
    const Eigen::VectorXd em = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m).eigenvalues();
    CHECK(em.minCoeff() >= ea.minCoeff() * (1 - 1e-12));
    CHECK(em.maxCoeff() <= ea.maxCoeff() * (1 + 1e-12));
    // The whole matrix when the rotations are kept and every connection too.
    CHECK(Eigen::MatrixXd(sys.sparsified(std::vector<uint8_t>(cs.size(), 1), false)) == a);
  }
}
