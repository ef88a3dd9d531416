// The balancing preconditioner: a Cholesky factor of an earlier matrix, corrected exactly on the
// span of W (silt/linalg.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "linalg/vector_ops.hpp"

namespace silt::linalg {
namespace {

// How many entries of E's lower triangle (E is stored whole, its pattern symmetric).
double lower_entries(const SparseMatrix& e) { return static_cast<double>(e.nonZeros() + e.rows()) / 2; }

// E's elimination order from the memory's: a column the memory holds keeps its place among those
// it holds; a new one goes right after the latest of its neighbours in E that the memory holds
// (eliminated there, it fills in about as the contact it touches did), or first when it has none.
// Empty when fewer than half the columns are in the memory.
std::vector<int> order_from(const CoarseCorrection::OrderMemory& memory, const std::vector<int64_t>& keys,
                            const SparseMatrix& e) {
  const int n = static_cast<int>(e.cols());
  std::vector<std::pair<int64_t, int>> old(memory.keys.size());
  for (size_t p = 0; p < old.size(); ++p) old[p] = {memory.keys[p], static_cast<int>(p)};
  std::sort(old.begin(), old.end());
  std::vector<int> place(static_cast<size_t>(n), -1);  // the position in the memory's order, -1 new
  int kept = 0;
  for (int c = 0; c < n; ++c) {
    const auto it = std::lower_bound(old.begin(), old.end(), std::pair{keys[c], std::numeric_limits<int>::min()});
    if (it != old.end() && it->first == keys[c]) {
      place[c] = it->second;
      ++kept;
    }
  }
  if (2 * kept < n) return {};
  std::vector<std::tuple<int, int, int>> rank(static_cast<size_t>(n));  // (place, new, column)
  for (int c = 0; c < n; ++c) {
    int at = place[c];
    if (at < 0)
      for (SparseMatrix::InnerIterator it(e, c); it; ++it) at = std::max(at, place[it.row()]);
    rank[c] = {at, place[c] < 0, c};
  }
  std::sort(rank.begin(), rank.end());
  std::vector<int> order(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) order[k] = std::get<2>(rank[k]);
  return order;
}

// E with its weak couplings moved onto its diagonal: each entry (c, d) of the lower triangle with
// |E_cd| < drop sqrt(E_cc E_dd) is removed, and |E_cd| added to E_cc and E_dd, which adds a
// positive semi-definite matrix (so the result stays definite); both triangles are made from the
// lower one, the only one CHOLMOD reads.
SparseMatrix drop_weak(const SparseMatrix& e, double drop) {
  const int m = static_cast<int>(e.cols());
  const Vector d = e.diagonal();
  Vector add = Vector::Zero(m);
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<size_t>(e.nonZeros()));
  for (int k = 0; k < m; ++k)
    for (SparseMatrix::InnerIterator it(e, k); it; ++it) {
      const int r = static_cast<int>(it.row());
      if (r <= k) continue;
      const double v = it.value();
      if (std::abs(v) < drop * std::sqrt(d[r] * d[k])) {
        add[r] += std::abs(v);
        add[k] += std::abs(v);
      } else {
        t.emplace_back(r, k, v);
        t.emplace_back(k, r, v);
      }
    }
  for (int k = 0; k < m; ++k) t.emplace_back(k, k, d[k] + add[k]);
  SparseMatrix out(m, m);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

}  // namespace

void CoarseCorrection::set_order_memory(OrderMemory m) {
  if (m.keys != memory_.keys || m.fill != memory_.fill) memory_replaced_ = true;
  memory_ = std::move(m);
}

// E analysed for a new pattern: from the memory's order when it fills the factor in little more
// than a fresh ordering did, else CHOLMOD's; the memory then holds the order analysed.
void CoarseCorrection::analyze_e(const SparseMatrix& e, const std::vector<int64_t>* keys) {
  const bool keyed = keys && static_cast<int64_t>(keys->size()) == e.cols();
  bool from_memory = false;
  if (keyed && !memory_.keys.empty() && memory_.fill > 0) {
    const std::vector<int> order = order_from(memory_, *keys, e);
    if (!order.empty()) {
      e_.analyze(e, &order);
      const auto entries = static_cast<double>(e_.factor_entries());  // 0 when CHOLMOD failed
      from_memory = entries > 0 && entries <= kOrderFillSlack * memory_.fill * lower_entries(e);
    }
  }
  if (from_memory) {
    ++kept_;
  } else {
    e_.analyze(e);
    memory_.fill = static_cast<double>(e_.factor_entries()) / lower_entries(e);
    ++fresh_;
  }
  if (!keyed) {
    memory_.keys.clear();
    return;
  }
  const std::vector<int> order = e_.order();
  memory_.keys.resize(order.size());
  for (size_t k = 0; k < order.size(); ++k) memory_.keys[k] = (*keys)[order[k]];
}

SolveReport CoarseCorrection::setup(const SparseMatrix& a, SparseMatrix& w, const Preconditioner& m,
                                    const std::vector<int64_t>* keys) {
  m_ = &m;
  w_.swap(w);  // Eigen's sparse matrices have no move
  w_.makeCompressed();
  ready_ = false;
  SolveReport rep;
  if (w_.cols() == 0) return rep;
  aw_ = sparse_product(a, w_);
  SparseMatrix e = sparse_product(SparseMatrix(w_.transpose()), aw_);
  // E is symmetric up to round-off (its (c, d) and (d, c) are summed in different orders), and
  // CHOLMOD reads its lower triangle. The diagonal raised by a relative 1e-10 keeps E definite
  // when W's columns are dependent.
  for (int64_t k = 0; k < e.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(e, k); it; ++it)
      if (it.row() == it.col()) it.valueRef() *= 1 + 1e-10;
  if (drop_ > 0) e = drop_weak(e, drop_);
  if (!e_.analysed_for(e) || memory_replaced_) analyze_e(e, keys);
  memory_replaced_ = false;
  rep = e_.factorize(e);
  ready_ = rep.ok();
  return rep;
}

// A enters only through A W, kept from the setup: A Q r = (A W) E^-1 W^T r, and, A being
// symmetric, W^T A z = (A W)^T z. No product with A itself.
void CoarseCorrection::apply(const Vector& r, Vector& z) const {
  if (!ready_) {
    m_->apply(r, z);
    return;
  }
  // ec = E^-1 W^T r, q = W ec = Q r
  transpose_times(w_, r, c_);
  (void)e_.solve(c_, ec_);
  q_.noalias() = w_ * ec_;
  // z = M^-1 (r - A q)
  y_ = r;
  y_.noalias() -= aw_ * ec_;
  m_->apply(y_, z);
  // z += q - Q A z
  transpose_times(aw_, z, c_);
  (void)e_.solve(c_, ec_);
  z += q_;
  z.noalias() -= w_ * ec_;
}

}  // namespace silt::linalg
