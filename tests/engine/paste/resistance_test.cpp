// The resistance matrix Xi = G^T xi G of Peyneau (2009) sec. 2.2, in 2D and 3D, against a direct
// computation of the lubrication forces, torques and stress (eq. 2.21-2.25, 2.31); its symmetry,
// positivity and kernel; the periodic chain's long-ranged mobility (eq. 2.49-2.53).
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>

#include "paste/resistance.hpp"

using namespace silt;
using namespace silt::paste;

namespace {

Eigen::Vector3d v3(const double* x) { return {x[0], x[1], x[2]}; }

// One connection between grains 0 and 1 with random geometry.
Connection random_connection(int dim, std::mt19937_64& rng, double ri, double rj) {
  std::normal_distribution<double> g;
  Eigen::Vector3d n(g(rng), g(rng), dim == 3 ? g(rng) : 0.0);
  n.normalize();
  const double gap = 0.05;
  Connection c;
  c.i = 0;
  c.j = 1;
  for (int a = 0; a < 3; ++a) {
    c.n[a] = n[a];
    c.r[a] = n[a] * (ri + rj + gap);
  }
  c.xi_n = 7.0;
  c.xi_t = 0.8;
  return c;
}

}  // namespace

TEST_CASE("-Xi V is the direct lubrication force, torque and stress of eq. 2.21-2.25 and 2.31") {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    for (int trial = 0; trial < 20; ++trial) {
      const double ri = 0.4 + 0.1 * trial / 20, rj = 0.5;
      const Connection c = random_connection(dim, rng, ri, rj);
      ResistanceLayout lay{dim, 2, true};
      const linalg::SparseMatrix xi = resistance_matrix(lay, {c}, {ri, rj});
      Eigen::VectorXd u(lay.size());
      for (int64_t k = 0; k < u.size(); ++k) u[k] = g(rng);
      if (dim == 2) u[lay.size() - 0 - 1] = g(rng);
      const Eigen::VectorXd f = -(xi * u);
      // The direct computation.
      Eigen::Vector3d vi = Eigen::Vector3d::Zero(), vj = vi, wi = vi, wj = vi, eps = vi;
      for (int a = 0; a < dim; ++a) {
        vi[a] = u[lay.velocity(0) + a];
        vj[a] = u[lay.velocity(1) + a];
        eps[a] = u[lay.strain_rate(a)];
      }
      if (dim == 2) {
        wi[2] = u[lay.spin(0)];
        wj[2] = u[lay.spin(1)];
      } else {
        for (int a = 0; a < 3; ++a) {
          wi[a] = u[lay.spin(0) + a];
          wj[a] = u[lay.spin(1) + a];
        }
      }
      const Eigen::Vector3d n = v3(c.n), r = v3(c.r);
      const Eigen::Vector3d vij = (vi - vj) + (ri * wi + rj * wj).cross(n) - eps.cwiseProduct(r);  // eq. 2.21
      const double vn = n.dot(vij);                                                                // eq. 2.22
      const Eigen::Vector3d vt = vij - vn * n;                                                     // eq. 2.23
      const Eigen::Vector3d fi = -c.xi_n * vn * n - c.xi_t * vt;                                   // eq. 2.24
      const Eigen::Vector3d ti = -ri * n.cross(c.xi_t * vt);                                       // eq. 2.25
      const Eigen::Vector3d tj = -rj * n.cross(c.xi_t * vt);
      for (int a = 0; a < dim; ++a) {
        CHECK(f[lay.velocity(0) + a] == doctest::Approx(fi[a]).epsilon(1e-12));
        CHECK(f[lay.velocity(1) + a] == doctest::Approx(-fi[a]).epsilon(1e-12));
        // The box rows: A sigma^lub_aa = F_(j<-i),a r_ij,a (eq. 2.31).
        CHECK(f[lay.strain_rate(a)] == doctest::Approx(-fi[a] * r[a]).epsilon(1e-12));
      }
      if (dim == 2) {
        CHECK(f[lay.spin(0)] == doctest::Approx(ti[2]).epsilon(1e-12));
        CHECK(f[lay.spin(1)] == doctest::Approx(tj[2]).epsilon(1e-12));
      } else {
        for (int a = 0; a < 3; ++a) {
          CHECK(f[lay.spin(0) + a] == doctest::Approx(ti[a]).epsilon(1e-12));
          CHECK(f[lay.spin(1) + a] == doctest::Approx(tj[a]).epsilon(1e-12));
        }
      }
    }
  }
}

TEST_CASE("Xi is symmetric positive semi-definite, definite when pinned and connected, and a loose grain is found") {
  // Grains on a square lattice, connected to their neighbours and along one diagonal (triangles:
  // see the next test for a graph without odd cycles).
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  const int side = 6, n = side * side;
  std::vector<Connection> cs;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (auto [di, dj] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}}) {
        if (i + di >= side || j + dj >= side) continue;
        Connection c;
        c.i = i * side + j;
        c.j = (i + di) * side + j + dj;
        const double len = std::hypot(di, dj);
        c.n[0] = di / len;
        c.n[1] = dj / len;
        c.r[0] = 2.1 * di;
        c.r[1] = 2.1 * dj;
        c.xi_n = 10 * u(rng);
        c.xi_t = u(rng);
        cs.push_back(c);
      }
  const std::vector<double> radius(n, 1.0);
  ResistanceLayout lay{2, n, false};
  const linalg::SparseMatrix xi = resistance_matrix(lay, cs, radius);
  CHECK((linalg::SparseMatrix(xi.transpose()) - xi).norm() < 1e-12 * xi.norm());
  std::normal_distribution<double> g;
  for (int k = 0; k < 10; ++k) {
    Eigen::VectorXd v(lay.size());
    for (int64_t m = 0; m < v.size(); ++m) v[m] = g(rng);
    CHECK(v.dot(xi * v) >= 0);
  }
  // A uniform translation is in the kernel.
  Eigen::VectorXd tr = Eigen::VectorXd::Zero(lay.size());
  for (int k = 0; k < n; ++k) tr[lay.velocity(k)] = 1;
  CHECK((xi * tr).norm() < 1e-12);
  // Grain 0's translation pinned (its rows and columns removed): definite when connected.
  auto pinned = [&](const linalg::SparseMatrix& a) {
    const Eigen::MatrixXd d(a);
    return linalg::SparseMatrix(d.bottomRightCorner(d.rows() - 2, d.cols() - 2).sparseView());
  };
  int32_t count = 0;
  connected_components(n, cs, count);
  CHECK(count == 1);
  linalg::CholeskyFactor f;
  CHECK(f.factorize(pinned(xi)).ok());
  // Grain 35 (a corner) loses its connections: two components, and the factorisation fails.
  std::vector<Connection> loose;
  for (const Connection& c : cs)
    if (c.j != n - 1) loose.push_back(c);
  const auto comp = connected_components(n, loose, count);
  CHECK(count == 2);
  CHECK(comp[n - 1] != comp[0]);
  CHECK(f.factorize(pinned(resistance_matrix(lay, loose, radius))).status == linalg::SolveStatus::kNotPositive);
}

TEST_CASE("the periodic chain: pinned, the mobility is T^-1_ij = (N - i) j / N, long-ranged (eq. 2.49-2.53)") {
  const int big_n = 12;
  const double xi_n = 3.0;
  std::vector<Connection> cs;
  for (int k = 0; k < big_n; ++k) {
    Connection c;
    c.i = k;
    c.j = (k + 1) % big_n;
    c.n[0] = 1;
    c.r[0] = 2.5;
    c.xi_n = xi_n;
    c.xi_t = 1.0;
    cs.push_back(c);
  }
  ResistanceLayout lay{2, big_n, false};
  const Eigen::MatrixXd xi(resistance_matrix(lay, cs, std::vector<double>(big_n, 1.0)));
  // The x translations of grains 1 .. N-1 (grain 0 pinned): xi_N tridiag(-1, 2, -1).
  Eigen::MatrixXd t(big_n - 1, big_n - 1);
  for (int a = 1; a < big_n; ++a)
    for (int b = 1; b < big_n; ++b) t(a - 1, b - 1) = xi(lay.velocity(a), lay.velocity(b)) / xi_n;
  const Eigen::MatrixXd inv = t.inverse();
  for (int i = 1; i < big_n; ++i)
    for (int j = 1; j <= i; ++j) CHECK(inv(i - 1, j - 1) == doctest::Approx(double(big_n - i) * j / big_n));
}

TEST_CASE("a connection graph without odd cycles lets the grains turn as gears: Xi is singular though connected") {
  // A square lattice, neighbours only: counter-rotating grains (omega = +w, -w on alternate sites)
  // slide nowhere, so <V, Xi V> = 0 for that V. Connectivity is necessary for Ker G = {0} but not
  // sufficient (it also needs an odd cycle); the dense random packings of the thesis have
  // triangles, a tree or a bipartite lattice does not.
  const int side = 4, n = side * side;
  std::vector<Connection> cs;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (auto [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (i + di >= side || j + dj >= side) continue;
        Connection c;
        c.i = i * side + j;
        c.j = (i + di) * side + j + dj;
        c.n[0] = di;
        c.n[1] = dj;
        c.xi_n = 5;
        c.xi_t = 1;
        cs.push_back(c);
      }
  ResistanceLayout lay{2, n, false};
  const linalg::SparseMatrix xi = resistance_matrix(lay, cs, std::vector<double>(n, 1.0));
  Eigen::VectorXd gears = Eigen::VectorXd::Zero(lay.size());
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) gears[lay.spin(i * side + j)] = (i + j) % 2 ? 1.0 : -1.0;
  CHECK((xi * gears).norm() < 1e-12);
  int32_t count = 0;
  connected_components(n, cs, count);
  CHECK(count == 1);
}
