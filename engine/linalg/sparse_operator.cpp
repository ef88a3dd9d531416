// Sparse products on several threads, each output entry summed by one thread in a fixed order:
// a symmetric matrix times a vector row by row (row i is column i of the compressed columns, read
// in place), a transposed matrix times a vector, and a matrix times a matrix column by column; and
// the Jacobi preconditioner.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "linalg/vector_ops.hpp"

namespace silt::linalg {

SparseOperator::SparseOperator(const SparseMatrix& a) : a_(a) {}

void SparseOperator::apply(const Vector& x, Vector& y) const {
  const int64_t n = a_.cols();
  y.resize(n);
  const int* outer = a_.outerIndexPtr();
  const int* inner = a_.innerIndexPtr();
  const double* val = a_.valuePtr();
  const int* counts = a_.innerNonZeroPtr();  // null when compressed
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, n, 1024), [&](const tbb::blocked_range<int64_t>& r) {
    const double* xv = x.data();
    for (int64_t i = r.begin(); i < r.end(); ++i) {
      // Four sums, entries k, k + 1, k + 2, k + 3 into each in turn, then (s0 + s1) + (s2 + s3)
      // and the rest: four chains of additions instead of one, the same order on any thread.
      double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
      const int begin = outer[i], end = counts ? begin + counts[i] : outer[i + 1];
      int k = begin;
      for (; k + 4 <= end; k += 4) {
        s0 += val[k] * xv[inner[k]];
        s1 += val[k + 1] * xv[inner[k + 1]];
        s2 += val[k + 2] * xv[inner[k + 2]];
        s3 += val[k + 3] * xv[inner[k + 3]];
      }
      double s = (s0 + s1) + (s2 + s3);
      for (; k < end; ++k) s += val[k] * xv[inner[k]];
      y[i] = s;
    }
  });
}

SparseMatrix sparse_product(const SparseMatrix& a, const SparseMatrix& b) {
  const int n = static_cast<int>(a.rows()), m = static_cast<int>(b.cols());
  // Columns in blocks of 64, each block's entries in its own lists, then copied in order.
  constexpr int kColumns = 64;
  const int blocks = (m + kColumns - 1) / kColumns;
  struct Part {
    std::vector<int> rows, counts;
    std::vector<double> values;
  };
  std::vector<Part> parts(static_cast<size_t>(blocks));
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& r) {
    // A thread's dense column, kept from call to call (a product per solve): all zero and unseen
    // between columns, as each column clears what it touched.
    thread_local std::vector<double> acc;
    thread_local std::vector<uint8_t> seen;
    thread_local std::vector<int> touched;
    if (acc.size() < static_cast<size_t>(n)) {
      acc.resize(static_cast<size_t>(n), 0.0);
      seen.resize(static_cast<size_t>(n), 0);
    }
    for (int blk = r.begin(); blk < r.end(); ++blk) {
      Part& p = parts[blk];
      for (int c = blk * kColumns; c < std::min(m, (blk + 1) * kColumns); ++c) {
        touched.clear();
        for (SparseMatrix::InnerIterator ib(b, c); ib; ++ib) {
          const double x = ib.value();
          for (SparseMatrix::InnerIterator ia(a, ib.row()); ia; ++ia) {
            const auto i = static_cast<int>(ia.row());
            if (!seen[i]) {
              seen[i] = 1;
              touched.push_back(i);
            }
            acc[i] += ia.value() * x;
          }
        }
        std::sort(touched.begin(), touched.end());
        for (int i : touched) {
          p.rows.push_back(i);
          p.values.push_back(acc[i]);
          acc[i] = 0;
          seen[i] = 0;
        }
        p.counts.push_back(static_cast<int>(touched.size()));
      }
    }
  });
  SparseMatrix out(n, m);
  int* outer = out.outerIndexPtr();
  outer[0] = 0;
  std::vector<int> first(static_cast<size_t>(blocks) + 1, 0);
  for (int blk = 0, c = 0; blk < blocks; ++blk) {
    first[blk + 1] = first[blk] + static_cast<int>(parts[blk].rows.size());
    for (int count : parts[blk].counts) {
      outer[c + 1] = outer[c] + count;
      ++c;
    }
  }
  out.resizeNonZeros(first[blocks]);
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& r) {
    for (int blk = r.begin(); blk < r.end(); ++blk) {
      std::copy(parts[blk].rows.begin(), parts[blk].rows.end(), out.innerIndexPtr() + first[blk]);
      std::copy(parts[blk].values.begin(), parts[blk].values.end(), out.valuePtr() + first[blk]);
    }
  });
  return out;
}

void transpose_times(const SparseMatrix& a, const Vector& x, Vector& y) {
  const int64_t m = a.cols();
  y.resize(m);
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, m, 256), [&](const tbb::blocked_range<int64_t>& r) {
    for (int64_t c = r.begin(); c < r.end(); ++c) {
      double s = 0;
      for (SparseMatrix::InnerIterator it(a, c); it; ++it) s += it.value() * x[it.row()];
      y[c] = s;
    }
  });
}

JacobiPreconditioner::JacobiPreconditioner(const SparseMatrix& a) : inv_diag_(a.rows()) {
  const Vector d = a.diagonal();
  for (int64_t i = 0; i < d.size(); ++i) {
    const bool good = d[i] > 0 && std::isfinite(d[i]);
    inv_diag_[i] = good ? 1 / d[i] : 1.0;
    if (!good && first_bad_ < 0) {
      first_bad_ = i;
      first_bad_value_ = d[i];
    }
  }
}

void JacobiPreconditioner::apply(const Vector& r, Vector& z) const { z = r.cwiseProduct(inv_diag_); }

}  // namespace silt::linalg
