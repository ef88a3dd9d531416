// Grain-grain contact forces over the Verlet list.
//
// For a listed pair (i, j) with d = x_i - x_j (nearest image), n = d/|d| points from j to i and
// the overlap is r_i + r_j - |d|. The relative velocity of i with respect to j at the contact
// point is
//   v_rel = v_i - v_j + G d - (r_i w_i + r_j w_j) x n,
// where G d is the difference of the affine box flow between the two centres (G = diag(dL/dt /
// L) under stress control, plus the shear rate at (x, y) under Lees-Edwards shear; zero
// otherwise). The force on i is F = F_n n + F_t (F_t from the tangential spring); j receives
// -F. The torque on i is (-r_i n) x F_t = -r_i (n x F_t), on j (r_j n) x (-F_t) = -r_j (n x F_t).
// Pairs that no longer touch drop their tangential history (LAMMPS gran/*/history).
// Both grains receive the pair's force and torque at once, in the order of the pair schedule
// (pair_schedule.hpp), which makes the sums independent of the number of threads; the force on
// i is also kept per pair (pair_f) for the stress and the contact network.
#include <bit>
#include <cmath>
#include <cstdint>
#include <algorithm>
#include <vector>

#include "core/parallel.hpp"
#include "core/small_vec.hpp"
#include "dem/contact_laws.hpp"
#include "dem/pair_schedule.hpp"
#include "dem/stages.hpp"
#include "shear/periodic_image.hpp"

namespace silt::dem {
namespace {

// Scratch of one task: the touching pairs of its rows, found by the first pass.
template <int D>
struct Touching {
  std::vector<int32_t> pair;
  std::vector<double> d;  // separation (nearest image), D per entry
  void reserve(size_t n) {
    if (pair.size() < n) {
      pair.resize(n);
      d.resize(D * n);
    }
  }
};

// Two passes per block of rows. The first tests every listed pair, zeroes the force and the
// history of those apart, and packs the touching ones without a branch; the second computes the
// laws for the packed list. In a flowing bed most listed pairs do not touch, in no predictable
// pattern: one loop with an `if` mispredicts on most pairs and stalls the pipeline.
template <int D, bool Hertz, bool Friction, bool Affine>
void pair_forces(const Model& m, State& s) {
  using V = SVec<D>;
  constexpr int R = kRotDim<D>;
  const ContactParams cp = m.contact;  // a copy: the loop keeps the parameters in registers
  const shear::PeriodicImage<D> img(s.box);
  const double dt = s.dt;
  const double max_overlap = m.limits.max_overlap;
  // Affine velocity gradient: stretching rates on the diagonal, the shear rate at (x, y).
  V grad = V::Zero();
  if constexpr (Affine)
    for (int k = 0; k < D; ++k) grad[k] = s.box_rate[k] / s.box.len[k];
  const double shear = s.shear_rate;
  const int64_t n = s.n;
  const double* __restrict x = s.particle_x.data();
  const double* __restrict v = s.particle_v.data();
  const double* __restrict w = s.particle_w.data();
  const double* __restrict r = s.particle_r.data();
  const double* __restrict im = s.particle_inv_m.data();
  const int32_t* __restrict start = s.nbr_start.data();
  const int32_t* __restrict pi = s.pair_i.data();
  const int32_t* __restrict pj = s.pair_j.data();
  double* __restrict pf = s.pair_f.data();
  double* __restrict hist = s.pair_hist.data();
  double* __restrict force = s.particle_f.data();
  double* __restrict torque = s.particle_t.data();
  Alarm* overlap_alarm = &s.alarm_overlap;
  parallel_for(n, 4096, [=](int64_t b, int64_t e) {
    std::fill(force + D * b, force + D * e, 0.0);
    if constexpr (Friction) std::fill(torque + R * b, torque + R * e, 0.0);
  });
  auto block = [=](int64_t blk) {
    const int64_t b = blk * PairSchedule::kBlock, e = std::min(n, b + PairSchedule::kBlock);
    thread_local Touching<D> tl;
    tl.reserve(static_cast<size_t>(start[e] - start[b]));
    int32_t* __restrict tp = tl.pair.data();
    double* __restrict td = tl.d.data();
    // Pass 1: which pairs touch, in one flat loop over the pairs of the block's rows (a loop
    // per row would mispredict its exit on rows of varying length).
    int64_t c = 0;
    for (int64_t p = start[b]; p < start[e]; ++p) {
      const int64_t i = pi[p], j = pj[p];
      V d = V::load(x + D * i) - V::load(x + D * j);
      img.apply(d);
      const double rs = r[i] + r[j];
      // All ones when touching, else zero: a mask, since a compare turned into a branch here
      // would mispredict on most pairs.
      const uint64_t keep = uint64_t{0} - static_cast<uint64_t>(d.squaredNorm() < rs * rs);
      V::Zero().store(pf + D * p);
      if constexpr (Friction) {
        double* __restrict h = hist + D * p;
        for (int k = 0; k < D; ++k) h[k] = std::bit_cast<double>(std::bit_cast<uint64_t>(h[k]) & keep);
      }
      tp[c] = static_cast<int32_t>(p);
      d.store(td + D * c);
      c += static_cast<int64_t>(keep & 1);
    }
    // Pass 2: the laws on the touching pairs, in row order, added to both grains.
    for (int64_t q = 0; q < c; ++q) {
      const int64_t p = tp[q], i = pi[p], j = pj[p];
      const V d = V::load(td + D * q);
      const double ri = r[i], rj = r[j];
      const double dist = d.norm();
      const V nrm = d * (1.0 / dist);
      const double overlap = ri + rj - dist;
      if (overlap > max_overlap * std::min(ri, rj)) overlap_alarm->raise(i, overlap / std::min(ri, rj));
      V vr = V::load(v + D * i) - V::load(v + D * j);
      if constexpr (Affine) {
        for (int k = 0; k < D; ++k) vr[k] += grad[k] * d[k];
        vr[0] += shear * d[1];
      }
      const double vn = vr.dot(nrm);
      const double m_eff = 1.0 / (im[i] + im[j]);
      NormalForce nf;
      if constexpr (Hertz) {
        nf = hertz_normal(cp.e_tilde, reduced_radius(ri, rj), cp.zeta, m_eff, overlap, -vn);
      } else {
        nf = linear_normal(linear_coeffs(cp, m_eff), overlap, -vn);
      }
      if (cp.clip_attractive) nf.fn = clip_attractive(nf.fn);
      V f = nf.fn * nrm;
      if constexpr (Friction) {
        const SOmega<D> wsum = ri * somega_load<D>(w, i) + rj * somega_load<D>(w, j);
        const V vt = vr - vn * nrm - cross_w(wsum, nrm);
        V spring = V::load(hist + D * p);
        const double kt = cp.kt_ratio * nf.k;
        const V ft = tangential_force(spring, nrm, vt, dt, kt, cp.friction * std::abs(nf.fn),
                                      tangential_dashpot(cp.zeta_t, m_eff, kt));
        spring.store(hist + D * p);
        f += ft;
        const SOmega<D> tc = moment(nrm, ft);
        somega_add<D>(torque, i, SOmega<D>(-ri * tc));
        somega_add<D>(torque, j, SOmega<D>(-rj * tc));
      }
      f.store(pf + D * p);
      for (int k = 0; k < D; ++k) {
        force[D * i + k] += f[k];
        force[D * j + k] -= f[k];
      }
    }
  };
  if (!s.scratch.schedule_valid) {
    s.scratch.schedule = build_pair_schedule(n, s.nbr_start, s.pair_j);
    s.scratch.schedule_valid = true;
  }
  const PairSchedule& sched = s.scratch.schedule;
  for (int col = 0; col < sched.colours(); ++col) {
    const int32_t* blocks = sched.blocks.data() + sched.colour_start[col];
    parallel_for(sched.colour_start[col + 1] - sched.colour_start[col], 1, [=](int64_t b, int64_t e) {
      for (int64_t k = b; k < e; ++k) block(blocks[k]);
    });
  }
}

template <int D>
void dispatch(const Model& m, State& s) {
  const bool hertz = m.contact.law == NormalLaw::kHertz;
  const bool fr = m.contact.friction > 0;
  const bool aff = m.box_control.on || m.shear.on;
#define SILT_CASE(H, F, A) \
  if (hertz == H && fr == F && aff == A) return pair_forces<D, H, F, A>(m, s);
  SILT_CASE(false, false, false)
  SILT_CASE(false, true, false)
  SILT_CASE(true, false, false)
  SILT_CASE(true, true, false)
  SILT_CASE(false, false, true)
  SILT_CASE(false, true, true)
  SILT_CASE(true, false, true)
  SILT_CASE(true, true, true)
#undef SILT_CASE
}

}  // namespace

void contact_forces(const Model& m, State& s) {
  if (m.dim == 2) dispatch<2>(m, s);
  else dispatch<3>(m, s);
}

}  // namespace silt::dem
