// The pressure operator A p = sigma p - Lap_h p of poisson_kernels.hpp as a linear operator
// (matrix-free, rows of cells in parallel) and as an assembled sparse matrix (for small grids:
// the direct reference, and the coarsest level of the multigrid hierarchy).
#pragma once

#include <algorithm>
#include <cstdint>

#include "core/parallel.hpp"
#include "fluid/grid.hpp"
#include "fluid/poisson_kernels.hpp"
#include "silt/linalg.hpp"

namespace silt::fluid {

// Whether A is singular: no Dirichlet face and sigma = 0 (then A 1 = 0).
bool poisson_singular(const Grid& g, double sigma);

// f(j, k) for every row of cells along x, rows in parallel. Each call writes the entries of its
// own row only, so the result does not depend on the partition or the number of threads.
template <class F>
void for_each_row(const std::array<int64_t, 3>& n, F&& f) {
  const int64_t rows = n[1] * n[2];
  const int64_t grain = std::max<int64_t>(1, 4096 / std::max<int64_t>(n[0], 1));  // ~4096 cells a task
  silt::parallel_for(rows, grain, [&](int64_t begin, int64_t end) {
    for (int64_t r = begin; r < end; ++r) f(r % n[1], r / n[1]);
  });
}

class PoissonOperator final : public linalg::LinearOperator {
 public:
  explicit PoissonOperator(const Grid& g, double sigma = 0);
  int64_t size() const override { return s_.cells(); }
  // y = A x (y is resized to the cells if needed).
  void apply(const linalg::Vector& x, linalg::Vector& y) const override;

  const Grid& grid() const { return grid_; }
  const PoissonStencil& stencil() const { return s_; }
  double sigma() const { return s_.sigma; }
  bool singular() const { return singular_; }

 private:
  Grid grid_;
  PoissonStencil s_;
  bool singular_ = false;
};

// A as a sparse matrix, both triangles, entries in the kernel's order of faces (so A x agrees
// with the matrix-free product to round-off). `pin_first_cell`: row and column 0 replaced by the
// identity's, which makes the singular operator definite; the solution of the pinned system
// with b_0 = 0 is the solution of A x = b (b of zero mean) whose first entry is 0.
linalg::SparseMatrix assemble_poisson(const Grid& g, double sigma, bool pin_first_cell = false);

}  // namespace silt::fluid
