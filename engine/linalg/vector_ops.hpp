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

}  // namespace silt::linalg
