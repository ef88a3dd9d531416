// Solves with a supernodal Cholesky factor L (A = P^T L L^T P), in parallel over the independent
// subtrees of its elimination tree and with the same bits on any number of threads.
//
// A supernode is a block of consecutive columns of L with one pattern of rows: a dense rectangle,
// its first rows the lower triangle of the diagonal block (Ng & Peyton 1993). Its column and rows
// in L's order are read from the factor as CHOLMOD leaves it (engine/linalg/cholmod_factor.cpp:
// the only file that knows CHOLMOD's types); nothing is copied, but for the values rounded to floats
// when a preconditioner asks for them (keep_single).
//
// The forward solve L y = P b takes the supernodes in their order (a child before its parent),
// the backward solve L^T z = y in the reverse order. Supernodes in disjoint subtrees touch
// disjoint unknowns, except that each adds its updates into the unknowns of its ancestors. The
// tree is cut, from its shape alone, into subtrees of at most a sixteenth of the factor's entries
// and the "top" above them (the largest separators). The subtrees run as parallel tasks (the small
// ones bundled), each adding its updates of the top into buffers of its own, which are then added
// into the top's unknowns in the tasks' order. The top's supernodes run in order; a large one
// shares each block of its columns among the threads, by rows in the forward solve (each row
// updated by the block's columns in their order) and by columns in the backward solve (each
// column's dot with the rows after the block, then the block's triangle on one thread). Which
// thread runs what changes no rounding. In the backward solve the top runs first, and each
// subtree then reads its ancestors' finished values.
//
// A supernode alone in its tree (no parent, no child, no row below its diagonal block: in 3D the
// 3 x 3 block of a grain's rotation when the factor keeps only the rotations' own blocks) is
// solved forward and back at once, all of them in one task beside the subtrees' forward tasks,
// with the operations it would take in a tree: thousands of them would otherwise each take a
// supernode's set-up twice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "silt/linalg.hpp"

namespace silt::linalg {

// A view of a supernodal factor, in CHOLMOD's layout (cholmod_factor, is_super).
struct SupernodalView {
  int64_t n = 0, nsuper = 0;
  const int* super = nullptr;  // [nsuper + 1] first column of each supernode
  const int* pi = nullptr;     // [nsuper + 1] start of each supernode's rows in s
  const int* px = nullptr;     // [nsuper + 1] start of each supernode's values in x
  const int* s = nullptr;      // row indices, each supernode's starting with its own columns
  const double* x = nullptr;   // values, each supernode a column-major rectangle
  const int* perm = nullptr;   // row k of L is row perm[k] of A (null: the identity)
};

class SupernodalSolver {
 public:
  // Reads the tree and cuts it into tasks; false if the factor is not in the order assumed (a
  // parent after its children, each subtree a contiguous range), and solve() must not be used.
  bool plan(const SupernodalView& f);
  // A copy of the factor's values in single precision, for solves that precondition: half the
  // bytes to read (the solves are bound by memory), sums still in double. False, and no copy, when
  // a value would not keep its relative precision as a float (beyond FLT_MAX or below FLT_MIN).
  bool keep_single();
  void drop_single() { single_ = {}; }
  bool has_single() const { return !single_.empty(); }
  // x = A^-1 b (b and x of n entries; they may not overlap), with the single-precision copy of
  // the factor when asked and kept (the solve of L~ L~^T, L~ the rounded factor: symmetric
  // positive definite as L~ has a positive diagonal). One solve at a time: the solver holds its
  // work arrays.
  void solve(const double* b, double* x, bool single = false) const;
  int64_t tasks() const { return static_cast<int64_t>(task_start_.size()) - 1; }
  const SolveSplit& split() const { return split_share_; }

 private:
  template <class T>
  void solve_with(const T* values, const double* b, double* x) const;
  template <class T>
  void forward(const T* values, int64_t sn, double* scratch, bool split) const;
  template <class T>
  void backward(const T* values, int64_t sn, double* scratch, bool split) const;
  template <class T>
  void alone(const T* values, int64_t sn) const;
  // f(supernode) over task t's subtrees, each in order (or in reverse order, the last first).
  template <class F>
  void for_task(int64_t t, bool reverse, F&& f) const {
    const size_t r0 = static_cast<size_t>(task_start_[static_cast<size_t>(t)]);
    const size_t r1 = static_cast<size_t>(task_start_[static_cast<size_t>(t) + 1]);
    for (size_t r = r0; r < r1; ++r) {
      const auto [first, last] = ranges_[reverse ? r0 + r1 - 1 - r : r];
      if (reverse)
        for (int64_t sn = last; sn >= first; --sn) f(sn);
      else
        for (int64_t sn = first; sn <= last; ++sn) f(sn);
    }
  }

  SupernodalView f_;
  std::vector<int64_t> top_;                         // supernodes of the top, in order
  std::vector<int64_t> alone_;                       // supernodes alone in their trees
  std::vector<std::pair<int64_t, int64_t>> ranges_;  // subtrees: first and last supernode
  std::vector<int64_t> task_start_;                  // [tasks + 1] each task's subtrees in ranges_
  std::vector<char> split_;                          // a top supernode shared among the threads
  std::vector<int64_t> buffer_start_;                // [tasks + 1] each task's buffers in work_ past n
  std::vector<int> buffer_row_;                      // the unknown each buffer entry adds into
  std::vector<int> target_;                          // where each row of s is updated in work_
  std::vector<int64_t> scratch_start_;               // [tasks + 2] scratch of each task, then the top
  SolveSplit split_share_;
  std::vector<float> single_;  // the factor's values rounded to floats (keep_single), or empty
  mutable std::vector<double> work_, scratch_;
};

}  // namespace silt::linalg
