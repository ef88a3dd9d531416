// Grain-grain contact forces over the Verlet list.
//
// For a listed pair (i, j) with d = x_i - x_j (nearest image), n = d/|d| points from j to i and
// the overlap is r_i + r_j - |d|. The relative velocity of i with respect to j at the contact
// point is
//   v_rel = v_i - v_j + G d - (r_i w_i + r_j w_j) x n,
// where G d is the difference of the affine box flow between the two centres (G = diag(dL/dt /
// L) under stress control; zero otherwise). The force on i is F = F_n n + F_t (F_t from the
// tangential spring); j receives -F. The torque on i is (-r_i n) x F_t = -r_i (n x F_t) and
// on j (r_j n) x (-F_t) = -r_j (n x F_t): pair_tc stores n x F_t once for both.
// Pairs that no longer touch drop their tangential history (LAMMPS gran/*/history).
// The sum over row i (the pairs where i is the first grain) is accumulated here into
// particle_f / particle_t; gather_kick adds the pairs where a grain is second.
#include <cmath>

#include "core/parallel.hpp"
#include "dem/box_geometry.hpp"
#include "dem/contact_laws.hpp"
#include "dem/stages.hpp"

namespace silt::dem {
namespace {

template <int D, bool Hertz, bool Friction, bool Affine>
void pair_forces(const Model& m, State& s) {
  const ContactParams& cp = m.contact;
  const PeriodicImage<D> img(s.box);
  const double dt = s.dt;
  const double max_overlap = m.limits.max_overlap;
  Vec<D> grad = Vec<D>::Zero();  // affine velocity gradient (diagonal)
  if constexpr (Affine)
    for (int k = 0; k < D; ++k) grad[k] = s.box_rate[k] / s.box.len[k];
  const double* __restrict x = s.particle_x.data();
  const double* __restrict v = s.particle_v.data();
  const double* __restrict w = s.particle_w.data();
  const double* __restrict r = s.particle_r.data();
  const double* __restrict im = s.particle_inv_m.data();
  const int32_t* __restrict start = s.nbr_start.data();
  const int32_t* __restrict pj = s.pair_j.data();
  double* __restrict pf = s.pair_f.data();
  double* __restrict ptc = s.pair_tc.data();
  double* __restrict hist = s.pair_hist.data();
  double* __restrict row_f = s.particle_f.data();
  double* __restrict row_t = s.particle_t.data();
  Alarm& overlap_alarm = s.alarm_overlap;
  parallel_for(s.n, 256, [&, x, v, w, r, im, start, pj, pf, ptc, hist, row_f, row_t](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) {
      const int32_t p0 = start[i], p1 = start[i + 1];
      Vec<D> fsum = Vec<D>::Zero();
      Omega<D> tsum{};
      if constexpr (D == 3) tsum = Vec3::Zero();
      const Vec<D> xi = at<D>(x, i);
      const double ri = r[i], imi = im[i];
      for (int32_t p = p0; p < p1; ++p) {
        const int32_t j = pj[p];
        Vec<D> d = xi - at<D>(x, j);
        img.apply(d);
        const double rs = ri + r[j];
        const double r2 = d.squaredNorm();
        if (r2 >= rs * rs) {
          at<D>(pf, p).setZero();
          if constexpr (Friction) at<D>(hist, p).setZero();
          continue;
        }
        const double dist = std::sqrt(r2);
        const Vec<D> n = d * (1.0 / dist);
        const double overlap = rs - dist;
        if (overlap > max_overlap * std::min(ri, r[j])) overlap_alarm.raise(i, overlap / std::min(ri, r[j]));
        Vec<D> vr = at<D>(v, i) - at<D>(v, j);
        if constexpr (Affine) vr += grad.cwiseProduct(d);
        const double vn = vr.dot(n);
        const double m_eff = 1.0 / (imi + im[j]);
        NormalForce nf;
        if constexpr (Hertz) {
          nf = hertz_normal(cp.e_tilde, reduced_radius(ri, r[j]), cp.zeta, m_eff, overlap, -vn);
        } else {
          nf = linear_normal(linear_coeffs(cp, m_eff), overlap, -vn);
        }
        if (cp.clip_attractive) nf.fn = clip_attractive(nf.fn);
        Vec<D> f = nf.fn * n;
        if constexpr (Friction) {
          const Omega<D> wsum = ri * omega_at<D>(w, i) + r[j] * omega_at<D>(w, j);
          const Vec<D> vt = vr - vn * n - cross_w(wsum, n);
          Vec<D> spring = at<D>(hist, p);
          const double kt = cp.kt_ratio * nf.k;
          const Vec<D> ft = tangential_force(spring, n, vt, dt, kt, cp.friction * std::abs(nf.fn),
                                             tangential_dashpot(cp.zeta_t, m_eff, kt));
          at<D>(hist, p) = spring;
          f += ft;
          const Omega<D> tc = moment(n, ft);
          omega_store<D>(ptc, p, tc);
          tsum += tc;
        }
        at<D>(pf, p) = f;
        fsum += f;
      }
      at<D>(row_f, i) = fsum;
      // Torque on i from its row: -r_i sum (n x F_t).
      if constexpr (Friction) omega_store<D>(row_t, i, Omega<D>(-ri * tsum));
    }
  });
}

template <int D>
void dispatch(const Model& m, State& s) {
  const bool hertz = m.contact.law == NormalLaw::kHertz;
  const bool fr = m.contact.friction > 0;
  const bool aff = m.box_control.on;
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
