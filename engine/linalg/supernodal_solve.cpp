#include "linalg/supernodal_solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "core/parallel.hpp"
#include "core/simd_level.hpp"

namespace silt::linalg {
namespace {

// Subtrees hold at most a kCut-th of the factor's entries each; subtrees smaller than a
// kBundle-th are bundled into tasks of about that size: enough tasks for two to four threads to
// share, few enough that each is a long run through memory.
constexpr int64_t kCut = 16, kBundle = 64;
// Columns of a supernode taken together; a supernode of more entries than kSplitEntries (a top
// separator) shares each block's rows (forward) or columns (backward) among the threads.
constexpr int64_t kCols = 128, kSplitEntries = int64_t{1} << 17, kSplitRows = 512;
// Below this many entries the whole factor is the top: a solve takes microseconds, less than
// handing tasks to threads.
constexpr int64_t kParallelEntries = int64_t{1} << 18;

// Eight doubles, one per chain of a sum (GCC's vector extension: one AVX-512 register, or two
// AVX2 or four SSE ones, with the same operations on each lane at every level).
using Lanes = double __attribute__((vector_size(64)));
using Floats = float __attribute__((vector_size(32)));
// (Taken and given by reference: a vector this wide passed by value has no ABI without AVX-512.)
inline void load(Lanes& v, const double* p) { std::memcpy(&v, p, sizeof v); }
// Eight floats of a single-precision factor, each made a double exactly.
inline void load(Lanes& v, const float* p) {
  Floats f;
  std::memcpy(&f, p, sizeof f);
  v = __builtin_convertvector(f, Lanes);
}
inline double join(const Lanes& c) { return ((c[0] + c[4]) + (c[1] + c[5])) + ((c[2] + c[6]) + (c[3] + c[7])); }

// sum_i a[i] b[i] in eight chains (i mod 8), joined in a fixed order (a of the factor's type T).
template <class T>
inline double dot(const T* a, const double* b, int64_t n) {
  Lanes c = {};
  int64_t i = 0;
  Lanes x, y;
  for (; i + 8 <= n; i += 8) {
    load(x, a + i);
    load(y, b + i);
    c += x * y;
  }
  for (int l = 0; i < n; ++i, ++l) c[l] += static_cast<double>(a[i]) * b[i];
  return join(c);
}

// dot(a[k], b, n) for k = 0..3, each summed exactly as dot() sums it: four streams through
// memory at once, b read once.
template <class T>
inline void dot4(const T* const* a, const double* b, int64_t n, double* out) {
  Lanes c0 = {}, c1 = {}, c2 = {}, c3 = {};
  int64_t i = 0;
  for (; i + 8 <= n; i += 8) {
    Lanes bi, x0, x1, x2, x3;
    load(bi, b + i);
    load(x0, a[0] + i);
    load(x1, a[1] + i);
    load(x2, a[2] + i);
    load(x3, a[3] + i);
    c0 += x0 * bi;
    c1 += x1 * bi;
    c2 += x2 * bi;
    c3 += x3 * bi;
  }
  for (int l = 0; i < n; ++i, ++l) {
    c0[l] += static_cast<double>(a[0][i]) * b[i];
    c1[l] += static_cast<double>(a[1][i]) * b[i];
    c2[l] += static_cast<double>(a[2][i]) * b[i];
    c3[l] += static_cast<double>(a[3][i]) * b[i];
  }
  out[0] = join(c0);
  out[1] = join(c1);
  out[2] = join(c2);
  out[3] = join(c3);
}

}  // namespace

bool SupernodalSolver::plan(const SupernodalView& f) {
  f_ = f;
  single_ = {};
  ranges_.clear();
  task_start_.assign(1, 0);
  top_.clear();
  alone_.clear();
  const int64_t ns = f.nsuper, n = f.n;
  std::vector<int> col_super(static_cast<size_t>(n));
  for (int64_t sn = 0; sn < ns; ++sn)
    for (int k = f.super[sn]; k < f.super[sn + 1]; ++k) col_super[static_cast<size_t>(k)] = static_cast<int>(sn);
  // The tree: a supernode's parent holds its first row below the diagonal block.
  std::vector<int64_t> parent(static_cast<size_t>(ns), -1), entries(static_cast<size_t>(ns)),
      subtree(static_cast<size_t>(ns)), first(static_cast<size_t>(ns));
  int64_t total = 0, max_rows = 0;
  for (int64_t sn = 0; sn < ns; ++sn) {
    const int64_t nc = f.super[sn + 1] - f.super[sn], nr = f.pi[sn + 1] - f.pi[sn];
    if (nr < nc) return false;
    for (int64_t j = 0; j < nc; ++j)
      if (f.s[f.pi[sn] + j] != f.super[sn] + j) return false;
    if (nr > nc) parent[static_cast<size_t>(sn)] = col_super[static_cast<size_t>(f.s[f.pi[sn] + nc])];
    if (parent[static_cast<size_t>(sn)] >= 0 && parent[static_cast<size_t>(sn)] <= sn) return false;
    entries[static_cast<size_t>(sn)] = nc * nr;
    total += nc * nr;
    max_rows = std::max(max_rows, nr);
  }
  // Subtree sizes and first supernodes; each subtree must be the range [first, root].
  for (int64_t sn = 0; sn < ns; ++sn) first[static_cast<size_t>(sn)] = sn;
  std::vector<int64_t> count(static_cast<size_t>(ns), 1);
  for (int64_t sn = 0; sn < ns; ++sn) {
    const size_t i = static_cast<size_t>(sn);
    subtree[i] += entries[i];
    if (sn - first[i] + 1 != count[i]) return false;
    if (parent[i] < 0) continue;
    const size_t p = static_cast<size_t>(parent[i]);
    subtree[p] += subtree[i];
    count[p] += count[i];
    first[p] = std::min(first[p], first[i]);
  }
  std::vector<std::vector<int64_t>> children(static_cast<size_t>(ns));
  std::vector<int64_t> open;  // subtrees not yet cut
  std::vector<char> is_alone(static_cast<size_t>(ns), 0);
  for (int64_t sn = 0; sn < ns; ++sn) {
    if (parent[static_cast<size_t>(sn)] >= 0)
      children[static_cast<size_t>(parent[static_cast<size_t>(sn)])].push_back(sn);
    else if (count[static_cast<size_t>(sn)] == 1 && f.pi[sn + 1] - f.pi[sn] <= kCols) {
      is_alone[static_cast<size_t>(sn)] = 1;  // no child (a subtree of one), no row below, one block
      alone_.push_back(sn);
    } else {
      open.push_back(sn);
    }
  }
  std::vector<char> in_top(static_cast<size_t>(ns), 0);
  if (total < kParallelEntries) {
    open.clear();
    for (int64_t sn = 0; sn < ns; ++sn) in_top[static_cast<size_t>(sn)] = !is_alone[static_cast<size_t>(sn)];
  }
  // Cut the largest open subtree at its root until each is small enough.
  while (!open.empty()) {
    const auto big = std::max_element(open.begin(), open.end(), [&](int64_t a, int64_t b) {
      return subtree[static_cast<size_t>(a)] < subtree[static_cast<size_t>(b)];
    });
    const int64_t root = *big;
    if (subtree[static_cast<size_t>(root)] * kCut <= total || children[static_cast<size_t>(root)].empty()) break;
    in_top[static_cast<size_t>(root)] = 1;
    open.erase(big);
    open.insert(open.end(), children[static_cast<size_t>(root)].begin(), children[static_cast<size_t>(root)].end());
  }
  // Tasks: each large subtree alone, the small ones bundled, largest first.
  std::sort(open.begin(), open.end(), [&](int64_t a, int64_t b) {
    const int64_t wa = subtree[static_cast<size_t>(a)], wb = subtree[static_cast<size_t>(b)];
    return wa != wb ? wa > wb : a < b;
  });
  int64_t in_tasks = 0, bundle = 0;
  for (int64_t sn : alone_) in_tasks += entries[static_cast<size_t>(sn)];
  task_start_.assign(1, 0);
  for (int64_t root : open) {
    const int64_t w = subtree[static_cast<size_t>(root)];
    ranges_.push_back({first[static_cast<size_t>(root)], root});
    in_tasks += w;
    bundle += w;
    if (bundle * kBundle >= total) {
      task_start_.push_back(static_cast<int64_t>(ranges_.size()));
      bundle = 0;
    }
  }
  if (task_start_.back() != static_cast<int64_t>(ranges_.size()))
    task_start_.push_back(static_cast<int64_t>(ranges_.size()));
  split_.assign(static_cast<size_t>(ns), 0);
  int64_t shared = 0;
  for (int64_t sn = 0; sn < ns; ++sn)
    if (in_top[static_cast<size_t>(sn)]) {
      top_.push_back(sn);
      split_[static_cast<size_t>(sn)] = entries[static_cast<size_t>(sn)] > kSplitEntries;
      if (split_[static_cast<size_t>(sn)]) shared += entries[static_cast<size_t>(sn)];
    }
  const double all = static_cast<double>(std::max<int64_t>(total, 1));
  split_share_ = {tasks(), static_cast<int64_t>(alone_.size()), static_cast<double>(in_tasks) / all,
                  static_cast<double>(shared) / all};
  // Where each row below a diagonal block is updated: the unknown itself, or, for a task's
  // update of the top, that task's buffer entry for the unknown.
  target_.assign(f.s, f.s + f.pi[ns]);
  buffer_row_.clear();
  buffer_start_.assign(1, n);
  scratch_start_.assign(1, 0);
  // Each subtree's rows below its diagonal blocks must be its own or the top's, and the top's
  // its own: true of an elimination tree, checked so that a factor in another form is refused.
  std::vector<int64_t> subtree_of(static_cast<size_t>(ns), -1);
  for (size_t r = 0; r < ranges_.size(); ++r)
    for (int64_t sn = ranges_[r].first; sn <= ranges_[r].second; ++sn)
      subtree_of[static_cast<size_t>(sn)] = static_cast<int64_t>(r);
  for (int64_t sn = 0; sn < ns; ++sn)
    for (int64_t k = f.pi[sn] + (f.super[sn + 1] - f.super[sn]); k < f.pi[sn + 1]; ++k) {
      const auto r = static_cast<size_t>(col_super[static_cast<size_t>(f.s[k])]);
      if (is_alone[r]) return false;  // (a row of it would make it an ancestor)
      const int64_t owner = subtree_of[r];
      if (owner >= 0 && owner != subtree_of[static_cast<size_t>(sn)]) return false;
    }
  std::vector<int> slot(static_cast<size_t>(n), -1);
  for (int64_t t = 0; t < tasks(); ++t) {
    const int64_t start = buffer_start_.back();
    int64_t rows = 0;
    for_task(t, false, [&](int64_t sn) {
      const int64_t nc = f.super[sn + 1] - f.super[sn];
      rows = std::max<int64_t>(rows, f.pi[sn + 1] - f.pi[sn]);
      for (int64_t k = f.pi[sn] + nc; k < f.pi[sn + 1]; ++k) {
        const int r = f.s[k];
        if (!in_top[static_cast<size_t>(col_super[static_cast<size_t>(r)])]) continue;
        int& sl = slot[static_cast<size_t>(r)];
        if (sl < 0) {
          sl = static_cast<int>(buffer_row_.size());
          buffer_row_.push_back(r);
        }
        target_[static_cast<size_t>(k)] = static_cast<int>(n) + sl;
      }
    });
    for (size_t j = static_cast<size_t>(start - n); j < buffer_row_.size(); ++j)
      slot[static_cast<size_t>(buffer_row_[j])] = -1;
    buffer_start_.push_back(n + static_cast<int64_t>(buffer_row_.size()));
    scratch_start_.push_back(scratch_start_.back() + rows);
  }
  scratch_start_.push_back(scratch_start_.back() + max_rows);
  work_.assign(static_cast<size_t>(buffer_start_.back()), 0.0);
  scratch_.assign(static_cast<size_t>(scratch_start_.back()), 0.0);
  return true;
}

bool SupernodalSolver::keep_single() {
  single_ = {};
  // The diagonal sets the scale: every diagonal entry at least 2^24 times the smallest normal float
  // (so what is not below a float's rounding of it stays a normal number) and no entry beyond
  // 2^-24 of the largest float. Entries below the smallest normal float are made zeros, not
  // subnormals (which would slow the arithmetic): they are below a float's rounding of every
  // diagonal entry, and L~ keeps its positive diagonal, so L~ L~^T stays positive definite.
  constexpr double kEps = 0x1p-24, kLow = std::numeric_limits<float>::min(), kHigh = std::numeric_limits<float>::max();
  for (int64_t sn = 0; sn < f_.nsuper; ++sn) {
    const int64_t nc = f_.super[sn + 1] - f_.super[sn], nr = f_.pi[sn + 1] - f_.pi[sn];
    for (int64_t j = 0; j < nc; ++j) {
      const double d = f_.x[f_.px[sn] + j * nr + j];
      if (!(d >= kLow / kEps && d <= kHigh * kEps)) return false;
    }
  }
  const int64_t count = f_.nsuper > 0 ? f_.px[f_.nsuper] : 0;
  for (int64_t k = 0; k < count; ++k)
    if (!(std::abs(f_.x[k]) <= kHigh * kEps)) return false;
  single_.resize(static_cast<size_t>(count));
  parallel_for(count, int64_t{1} << 16, [&](int64_t k0, int64_t k1) {
    for (int64_t k = k0; k < k1; ++k) {
      const double v = f_.x[k];
      single_[static_cast<size_t>(k)] = std::abs(v) < kLow ? 0.0f : static_cast<float>(v);
    }
  });
  return true;
}

namespace {

// x = L^-1 x on the triangle of columns [jb, je) of a supernode (column j at l + j nr), four
// columns at a time: their own triangle, then the rows below it in the block updated by the four
// in their order. Each entry takes the same operations in the same order as one column at a
// time, with a quarter of the loads and stores.
template <class T>
inline void block_triangle(const T* l, int64_t nr, int64_t jb, int64_t je, double* x) {
  int64_t j = jb;
  for (; j + 4 <= je; j += 4) {
    const T *c0 = l + j * nr, *c1 = c0 + nr, *c2 = c1 + nr, *c3 = c2 + nr;
    const double x0 = x[j] / c0[j];
    x[j] = x0;
    x[j + 1] -= c0[j + 1] * x0;
    x[j + 2] -= c0[j + 2] * x0;
    x[j + 3] -= c0[j + 3] * x0;
    const double x1 = x[j + 1] / c1[j + 1];
    x[j + 1] = x1;
    x[j + 2] -= c1[j + 2] * x1;
    x[j + 3] -= c1[j + 3] * x1;
    const double x2 = x[j + 2] / c2[j + 2];
    x[j + 2] = x2;
    x[j + 3] -= c2[j + 3] * x2;
    const double x3 = x[j + 3] / c3[j + 3];
    x[j + 3] = x3;
    SILT_IVDEP
    for (int64_t i = j + 4; i < je; ++i) x[i] = (((x[i] - c0[i] * x0) - c1[i] * x1) - c2[i] * x2) - c3[i] * x3;
  }
  for (; j < je; ++j) {
    const T* c = l + j * nr;
    const double xj = x[j] / c[j];
    x[j] = xj;
    SILT_IVDEP
    for (int64_t i = j + 1; i < je; ++i) x[i] -= c[i] * xj;
  }
}

}  // namespace

// y_s = L_ss^-1 y_s, then the rows below: y_r -= L_rs y_s (into a buffer for a task's top rows).
// Block by block of kCols columns: the block's triangle, then its update of the rows after it,
// each row updated by the columns in their order whatever the split of the rows.
template <class T>
void SupernodalSolver::forward(const T* values, int64_t sn, double* y, bool split) const {
  const int64_t k0 = f_.super[sn], nc = f_.super[sn + 1] - k0, p0 = f_.pi[sn], nr = f_.pi[sn + 1] - p0, m = nr - nc;
  const T* l = values + f_.px[sn];
  double* w = work_.data();
  double* xs = w + k0;
  std::fill(y, y + m, 0.0);
  for (int64_t jb = 0; jb < nc; jb += kCols) {
    const int64_t je = std::min(nc, jb + kCols);
    run_simd([&] { block_triangle(l, nr, jb, je, xs); });
    auto rows = [&](int64_t r0, int64_t r1) {
      run_simd([&] {
        const int64_t a1 = std::min(r1, nc), b0 = std::max(r0, nc);
        double* yb = y - nc;
        int64_t j = jb;
        // Four columns at a time, each row updated by them in order (the same operations as
        // one column at a time, with a quarter of the loads and stores of the rows).
        for (; j + 4 <= je; j += 4) {
          const T *c0 = l + j * nr, *c1 = c0 + nr, *c2 = c1 + nr, *c3 = c2 + nr;
          const double x0 = xs[j], x1 = xs[j + 1], x2 = xs[j + 2], x3 = xs[j + 3];
          SILT_IVDEP
          for (int64_t i = r0; i < a1; ++i) xs[i] = (((xs[i] - c0[i] * x0) - c1[i] * x1) - c2[i] * x2) - c3[i] * x3;
          SILT_IVDEP
          for (int64_t i = b0; i < r1; ++i) yb[i] = (((yb[i] + c0[i] * x0) + c1[i] * x1) + c2[i] * x2) + c3[i] * x3;
        }
        for (; j < je; ++j) {
          const T* c = l + j * nr;
          const double xj = xs[j];
          SILT_IVDEP
          for (int64_t i = r0; i < a1; ++i) xs[i] -= c[i] * xj;
          SILT_IVDEP
          for (int64_t i = b0; i < r1; ++i) yb[i] += c[i] * xj;
        }
      });
    };
    if (!split) {
      rows(je, nr);
      continue;
    }
    const int64_t chunks = (nr - je + kSplitRows - 1) / kSplitRows;
    parallel_for(chunks, 1, [&](int64_t c0, int64_t c1) {
      for (int64_t c = c0; c < c1; ++c) rows(je + c * kSplitRows, std::min(nr, je + (c + 1) * kSplitRows));
    });
  }
  const int* tg = target_.data() + p0 + nc;
  for (int64_t i = 0; i < m; ++i) w[tg[i]] -= y[i];
}

// z_s = L_ss^-T (z_s - L_rs^T z_r), the rows r below read where they are finished. Block by
// block of kCols columns from the last: each column's dot with the rows after the block (the
// columns shared among the threads when split), then the block's triangle.
template <class T>
void SupernodalSolver::backward(const T* values, int64_t sn, double* t, bool split) const {
  const int64_t k0 = f_.super[sn], nc = f_.super[sn + 1] - k0, p0 = f_.pi[sn], nr = f_.pi[sn + 1] - p0;
  const T* l = values + f_.px[sn];
  double* w = work_.data();
  std::copy(w + k0, w + k0 + nc, t);
  for (int64_t i = nc; i < nr; ++i) t[i] = w[f_.s[p0 + i]];
  double after[kCols];
  for (int64_t jb = (nc - 1) / kCols * kCols; jb >= 0; jb -= kCols) {
    const int64_t je = std::min(nc, jb + kCols);
    auto columns = [&](int64_t j0, int64_t j1) {
      run_simd([&] {
        int64_t j = j0;
        for (; j + 4 <= j1; j += 4) {
          const T* c[4] = {l + j * nr + je, l + (j + 1) * nr + je, l + (j + 2) * nr + je, l + (j + 3) * nr + je};
          dot4(c, t + je, nr - je, after + (j - jb));
        }
        for (; j < j1; ++j) after[j - jb] = dot(l + j * nr + je, t + je, nr - je);
      });
    };
    if (split) {
      parallel_for(je - jb, 8, [&](int64_t c0, int64_t c1) { columns(jb + c0, jb + c1); });
    } else {
      columns(jb, je);
    }
    run_simd([&] {
      for (int64_t j = je - 1; j >= jb; --j) {
        const T* c = l + j * nr;
        t[j] = (t[j] - after[j - jb] - dot(c + j + 1, t + j + 1, je - j - 1)) / c[j];
      }
    });
  }
  std::copy(t, t + nc, w + k0);
}

// A supernode alone in its tree, forward then back in place: what forward() and backward() do to it
// (its columns in one block, no row below: no update to add, and each column's dot with the rows
// after the block a sum of nothing, 0, which leaves the difference it is taken from as it is).
template <class T>
void SupernodalSolver::alone(const T* values, int64_t sn) const {
  const int64_t k0 = f_.super[sn], nc = f_.super[sn + 1] - k0;
  const T* l = values + f_.px[sn];
  double* t = work_.data() + k0;
  block_triangle(l, nc, 0, nc, t);
  for (int64_t j = nc - 1; j >= 0; --j) {
    const T* c = l + j * nc;
    t[j] = (t[j] - dot(c + j + 1, t + j + 1, nc - j - 1)) / c[j];
  }
}

void SupernodalSolver::solve(const double* b, double* x, bool single) const {
  if (single && !single_.empty()) solve_with(single_.data(), b, x);
  else solve_with(f_.x, b, x);
}

template <class T>
void SupernodalSolver::solve_with(const T* values, const double* b, double* x) const {
  const int64_t n = f_.n, tasks = this->tasks();
  double* w = work_.data();
  for (int64_t k = 0; k < n; ++k) w[k] = b[f_.perm ? f_.perm[k] : k];
  std::fill(w + n, w + buffer_start_.back(), 0.0);
  double* top_scratch = scratch_.data() + scratch_start_[static_cast<size_t>(tasks)];
  // The supernodes alone in their trees are one more forward task, the last.
  const bool with_alone = !alone_.empty();
  auto each_task = [&](bool reverse) {
    tbb::parallel_for(
        tbb::blocked_range<int64_t>(0, tasks + (reverse ? 0 : with_alone), 1),
        [&](const tbb::blocked_range<int64_t>& r) {
          for (int64_t t = r.begin(); t < r.end(); ++t) {
            if (t == tasks) {
              run_simd([&] {
                for (int64_t sn : alone_) alone(values, sn);
              });
              continue;
            }
            double* scratch = scratch_.data() + scratch_start_[static_cast<size_t>(t)];
            run_simd([&] {
              for_task(t, reverse, [&](int64_t sn) {
                if (reverse) backward(values, sn, scratch, false);
                else forward(values, sn, scratch, false);
              });
            });
          }
        },
        tbb::simple_partitioner{});
  };
  each_task(false);
  for (int64_t j = n; j < buffer_start_.back(); ++j) w[buffer_row_[static_cast<size_t>(j - n)]] += w[j];
  // The top in order, the supernodes too small to share inside one choice of instructions.
  auto top = [&](bool reverse) {
    for (size_t k = 0; k < top_.size();) {
      auto node = [&](size_t i) { return top_[reverse ? top_.size() - 1 - i : i]; };
      auto one = [&](int64_t sn, bool split) {
        if (reverse) backward(values, sn, top_scratch, split);
        else forward(values, sn, top_scratch, split);
      };
      if (split_[static_cast<size_t>(node(k))]) {
        one(node(k++), true);
        continue;
      }
      run_simd([&] {
        for (; k < top_.size() && !split_[static_cast<size_t>(node(k))]; ++k) one(node(k), false);
      });
    }
  };
  top(false);
  top(true);
  each_task(true);
  for (int64_t k = 0; k < n; ++k) x[f_.perm ? f_.perm[k] : k] = w[k];
}

}  // namespace silt::linalg
