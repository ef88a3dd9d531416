// Vector operations of the solvers, in parallel and deterministic: a reduction is summed in fixed
// blocks of kBlock entries, each block in order, then the blocks in order, so its rounding does
// not depend on the number of threads.
#pragma once

#include "silt/linalg.hpp"

namespace silt::linalg {

constexpr int64_t kBlock = 4096;

double dot(const Vector& a, const Vector& b);
// y += alpha x
void axpy(double alpha, const Vector& x, Vector& y);
// p = z + beta p
void xpby(const Vector& z, double beta, Vector& p);
bool all_finite(const Vector& v);
// A B of two sparse matrices, the columns of the product on several threads: column c sums, for
// each entry of B's column c in its order, A's column times it, as Eigen's product does, so the
// bits are Eigen's and the same on any number of threads.
SparseMatrix sparse_product(const SparseMatrix& a, const SparseMatrix& b);
// y = A^T x, each entry a column's dot product in its order (Eigen's bits), on several threads.
void transpose_times(const SparseMatrix& a, const Vector& x, Vector& y);

}  // namespace silt::linalg
