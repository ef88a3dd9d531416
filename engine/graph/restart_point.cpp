#include "graph/restart_point.hpp"

#include <utility>

#include "core/buffers.hpp"

namespace silt::graph {
namespace {

// Moves the three per-pair arrays out of a State for its lifetime, and back.
struct PairArraysAside {
  explicit PairArraysAside(State& s) : s_(s) { swap(); }
  ~PairArraysAside() { swap(); }
  PairArraysAside(const PairArraysAside&) = delete;
  PairArraysAside& operator=(const PairArraysAside&) = delete;
  void swap() {
    pair_i.swap(s_.pair_i);
    pair_f.swap(s_.pair_f);
    pair_hist.swap(s_.pair_hist);
  }
  State& s_;
  std::vector<int32_t> pair_i;
  std::vector<double> pair_f, pair_hist;
};

}  // namespace

void RestartPoint::take(State& s) {
  const int D = s.dim;
  held_.clear();
  held_f_.clear();
  held_hist_.clear();
  const int64_t np = static_cast<int64_t>(s.pair_f.size()) / D;
  for (int64_t p = 0; p < np; ++p) {
    const double* f = &s.pair_f[D * p];
    const double* h = &s.pair_hist[D * p];
    if (!any_bit_set(f, D) && !any_bit_set(h, D)) continue;
    held_.push_back(static_cast<int32_t>(p));
    held_f_.insert(held_f_.end(), f, f + D);
    held_hist_.insert(held_hist_.end(), h, h + D);
  }
  const PairArraysAside aside(s);
  base_ = s;
}

State RestartPoint::give() const {
  State s = base_;
  const int D = s.dim;
  const int64_t np = s.n_pairs();
  s.pair_i.resize(np);
  for (int64_t i = 0; i + 1 < static_cast<int64_t>(s.nbr_start.size()); ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) s.pair_i[p] = static_cast<int32_t>(i);
  s.pair_f.assign(np * D, 0.0);
  s.pair_hist.assign(np * D, 0.0);
  for (size_t k = 0; k < held_.size(); ++k)
    for (int c = 0; c < D; ++c) {
      s.pair_f[D * held_[k] + c] = held_f_[D * k + c];
      s.pair_hist[D * held_[k] + c] = held_hist_[D * k + c];
    }
  return s;
}

}  // namespace silt::graph
