// The pressure operator, matrix-free and assembled; see poisson_kernels.hpp for the stencil and
// its boundary conditions.
#include "fluid/poisson_operator.hpp"

#include <vector>

namespace silt::fluid {

bool poisson_singular(const Grid& g, double sigma) {
  if (sigma != 0) return false;
  for (int a = 0; a < g.dim; ++a)
    for (int side = 0; side < 2; ++side)
      if (g.pbc(a, side) == PressureBc::kDirichlet) return false;
  return true;
}

PoissonOperator::PoissonOperator(const Grid& g, double sigma)
    : grid_(g), s_(make_poisson_stencil(g, sigma)), singular_(poisson_singular(g, sigma)) {}

void PoissonOperator::apply(const linalg::Vector& x, linalg::Vector& y) const {
  y.resize(size());
  const double* xp = x.data();
  double* yp = y.data();
  const PoissonStencil& s = s_;
  for_each_row(s.n, [&](int64_t j, int64_t k) {
    const int64_t row = s.stride[1] * j + s.stride[2] * k;
    const bool inside = poisson_row_inside(s, j, k);
    for (int64_t i = 0; i < s.n[0]; ++i) yp[row + i] = poisson_apply_fast(s, inside, i, j, k, xp);
  });
}

linalg::SparseMatrix assemble_poisson(const Grid& g, double sigma, bool pin_first_cell) {
  const PoissonStencil s = make_poisson_stencil(g, sigma);
  const int64_t n = s.cells();
  // Each face of each cell adds w_a to the diagonal and -w_a to the neighbour's column (or,
  // through a ghost worth sign * p_c, -sign w_a to the diagonal): the kernel's sum, term by term.
  // Duplicate entries (a periodic axis of one or two cells) are summed by setFromTriplets.
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(n * (1 + 2 * s.dim)));
  for (int64_t k = 0; k < s.n[2]; ++k)
    for (int64_t j = 0; j < s.n[1]; ++j)
      for (int64_t i = 0; i < s.n[0]; ++i) {
        const std::array<int64_t, 3> idx{i, j, k};
        const int64_t c = i + s.stride[1] * j + s.stride[2] * k;
        double diag = s.sigma;
        for (int a = 0; a < s.dim; ++a)
          for (int side = 0; side < 2; ++side) {
            const Across x = across(s, a, side, idx[a]);
            diag += s.w[a];
            if (x.ghost) diag -= x.ghost_sign * s.w[a];
            else t.emplace_back(static_cast<int>(c), static_cast<int>(c + x.offset), -s.w[a]);
          }
        t.emplace_back(static_cast<int>(c), static_cast<int>(c), diag);
      }
  if (pin_first_cell) {
    std::erase_if(t, [](const Eigen::Triplet<double>& e) { return e.row() == 0 || e.col() == 0; });
    t.emplace_back(0, 0, 1.0);
  }
  linalg::SparseMatrix a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

}  // namespace silt::fluid
