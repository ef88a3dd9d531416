#include "paste/resistance.hpp"

#include "paste/system.hpp"

#include <cmath>
#include <numeric>

namespace silt::paste {

void tangents(int dim, const double* n, double t[2][3]) {
  if (dim == 2) {
    t[0][0] = -n[1];
    t[0][1] = n[0];
    t[0][2] = 0;
    return;
  }
  // The axis least aligned with n, crossed with it.
  const int k = std::abs(n[0]) <= std::abs(n[1]) && std::abs(n[0]) <= std::abs(n[2]) ? 0
                : std::abs(n[1]) <= std::abs(n[2])                                   ? 1
                                                                                     : 2;
  double e[3] = {0, 0, 0};
  e[k] = 1;
  double a[3] = {n[1] * e[2] - n[2] * e[1], n[2] * e[0] - n[0] * e[2], n[0] * e[1] - n[1] * e[0]};
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  for (double& x : a) x /= la;
  const double b[3] = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
  for (int m = 0; m < 3; ++m) {
    t[0][m] = a[m];
    t[1][m] = b[m];
  }
}

linalg::SparseMatrix connection_map(const ResistanceLayout& L, const std::vector<Connection>& cs,
                                    const std::vector<double>& radius) {
  // The rows of each connection (paste/system.hpp), in the layout's numbering: every box axis
  // an unknown.
  const bool all[3] = {true, true, true};
  const SystemLayout sl = make_layout(L.dim, L.grains, L.box ? all : nullptr, false);
  const int n = local_size(sl), d = L.dim;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(cs.size() * static_cast<size_t>(d * n));
  std::vector<double> g(static_cast<size_t>(d * n));
  for (size_t k = 0; k < cs.size(); ++k) {
    local_map(sl, cs[k], radius[cs[k].i], radius[cs[k].j], g.data());
    for (int row = 0; row < d; ++row)
      for (int q = 0; q < n; ++q)
        if (g[row * n + q] != 0)
          t.emplace_back(static_cast<int>(k * d + row), static_cast<int>(local_to_global(sl, cs[k], q)),
                         g[row * n + q]);
  }
  linalg::SparseMatrix gm(static_cast<int64_t>(cs.size()) * d, L.size());
  gm.setFromTriplets(t.begin(), t.end());
  gm.makeCompressed();
  return gm;
}

linalg::SparseMatrix resistance_matrix(const ResistanceLayout& L, const std::vector<Connection>& cs,
                                       const std::vector<double>& radius) {
  const linalg::SparseMatrix g = connection_map(L, cs, radius);
  Eigen::VectorXd xi(g.rows());
  for (size_t k = 0; k < cs.size(); ++k)
    for (int q = 0; q < L.dim; ++q) xi[static_cast<int64_t>(k) * L.dim + q] = q == 0 ? cs[k].xi_n : cs[k].xi_t;
  linalg::SparseMatrix xi_g = xi.asDiagonal() * g;
  linalg::SparseMatrix a = (g.transpose() * xi_g).pruned();
  a.makeCompressed();
  return a;
}

std::vector<int32_t> connected_components(int64_t grains, const std::vector<Connection>& cs, int32_t& count) {
  std::vector<int32_t> parent(static_cast<size_t>(grains));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Connection& c : cs) {
    const int32_t a = find(c.i), b = find(c.j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<int32_t> comp(static_cast<size_t>(grains), -1), id(static_cast<size_t>(grains), -1);
  count = 0;
  for (int64_t g = 0; g < grains; ++g) {
    const int32_t root = find(static_cast<int32_t>(g));
    if (id[root] < 0) id[root] = count++;
    comp[g] = id[root];
  }
  return comp;
}

}  // namespace silt::paste
