// Contact laws as pure functions. Conventions: `overlap` = r_i + r_j - |x_i - x_j| > 0 in
// contact; `overlap_rate` = d(overlap)/dt (> 0 while approaching); m_eff = m_i m_j / (m_i + m_j),
// with m_eff = m_i against a wall or a frozen grain (infinite mass). Forces are repulsive when
// positive. SI units throughout (in 2D, masses and stiffnesses are per unit thickness).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "silt/model.hpp"

namespace silt::dem {

struct NormalForce {
  double fn;  // normal force magnitude along n (repulsive > 0) [N]
  double k;   // current normal stiffness dF/d(overlap) [N/m], for the tangential spring
};

// Linear spring-dashpot stiffness and dashpot from a restitution e and a contact time t_c.
// Izard (2014) eq. 3.16-3.17 (Schafer et al. 1996):
//   gamma_n = -(2 m*/t_c) ln e,   k_n = m* pi^2 / t_c^2 + gamma_n^2 / (4 m*),
// both proportional to m*: per unit reduced mass, k_n / m* = (pi^2 + ln^2 e) / t_c^2 and
// gamma_n / m* = -2 ln e / t_c (ContactParams k1 and c1 of the linear family). With this choice
// the half period of the damped oscillator is exactly t_c and the rebound velocity is exactly e
// times the impact velocity (without clipping). Valid 0 < e <= 1.
struct LinearCoeffs {
  double k, c;
};
inline LinearCoeffs spring_dashpot_rates(double e, double t_c) {
  const double ln_e = std::log(e);
  return {(std::numbers::pi * std::numbers::pi + ln_e * ln_e) / (t_c * t_c), -2.0 * ln_e / t_c};
}

// The linear family (spring_dashpot, hooke, linear): F_n = k_n overlap + c_n overlap_rate with
//   k_n = k0 + k1 m*,  c_n = c1 m* + 2 zeta sqrt(m* k_n).
// hooke is LAMMPS gran/hooke (dashpot m* gamma_n); linear is Peyneau (2009) eq. 1.23 for disks
// with a dashpot at a fraction zeta of critical damping.
inline LinearCoeffs linear_coeffs(const ContactParams& p, double m_eff) {
  const double k = p.k0 + p.k1 * m_eff;
  double c = p.c1 * m_eff;
  if (p.zeta > 0) c += 2.0 * p.zeta * std::sqrt(m_eff * k);
  return {k, c};
}
inline NormalForce linear_normal(const LinearCoeffs& kc, double overlap, double overlap_rate) {
  return {kc.k * overlap + kc.c * overlap_rate, kc.k};
}

// Hertz's elastic coefficient k_h of F_e = k_h h^(3/2): (E~/3) sqrt(2 R_eq).
inline double hertz_coefficient(double e_tilde, double r_eq) { return e_tilde / 3.0 * std::sqrt(2.0 * r_eq); }

// Hertz with a viscous dashpot, Peyneau (2009) eq. 1.22 and 3.1-3.3:
//   F_e = (E~/3) sqrt(2 R_eq) h^(3/2),   K_N = dF_e/dh = (E~/2) sqrt(2 R_eq h),
//   F_v = zeta sqrt(2 m K_N) dh/dt  for two grains of mass m, i.e. 2 zeta sqrt(m* K_N) dh/dt,
// with E~ = E/(1 - nu^2) and 2/R_eq = 1/R_i + 1/R_j (R_eq = 2 R_i against a wall).
inline NormalForce hertz_normal(double e_tilde, double r_eq, double zeta, double m_eff, double overlap,
                                double overlap_rate) {
  const double s = std::sqrt(2.0 * r_eq * overlap);
  const double k = 0.5 * e_tilde * s;
  const double fe = (e_tilde / 3.0) * s * overlap;
  return {fe + 2.0 * zeta * std::sqrt(m_eff * k) * overlap_rate, k};
}

// Duration of an undamped Hertz collision in units of (m*/k_h)^(2/5) v^(-1/5), F = k_h h^(3/2),
// v the impact speed (Johnson 1985, sec. 11.4): t = 2 int_0^h_m dh / sqrt(v^2 - (4/5)(k_h/m*) h^(5/2))
// = 2 (2/5) B(2/5, 1/2) h_m / v with h_m = (5 m* v^2 / (4 k_h))^(2/5), so the constant is
// 2 (2/5) B(2/5, 1/2) (5/4)^(2/5) = 3.21807...
inline double hertz_duration() {
  static const double c = 2.0 * 0.4 * std::beta(0.4, 0.5) * std::pow(1.25, 0.4);
  return c;
}

// Reduced radius of Peyneau (2009) eq. 1.22: 2/R_eq = 1/R_i + 1/R_j.
inline double reduced_radius(double ri, double rj) { return 2.0 * ri * rj / (ri + rj); }

// Izard (2014) eq. 3.13: the dashpot may not pull the grains together.
inline double clip_attractive(double fn) { return fn > 0.0 ? fn : 0.0; }

// The normal law of the scene, Hertz or the linear family, without clipping: the one dispatch
// (the pair loop takes it as a template argument, walls and reports at run time).
template <bool Hertz>
inline NormalForce normal_law(const ContactParams& p, double m_eff, double r_eq, double overlap, double overlap_rate) {
  if constexpr (Hertz) return hertz_normal(p.e_tilde, r_eq, p.zeta, m_eff, overlap, overlap_rate);
  else return linear_normal(linear_coeffs(p, m_eff), overlap, overlap_rate);
}

// Normal force of the scene's law for one contact, clipped when the scene says so.
inline NormalForce normal_force(const ContactParams& p, double m_eff, double r_eq, double overlap,
                                double overlap_rate) {
  NormalForce f = p.law == NormalLaw::kHertz ? normal_law<true>(p, m_eff, r_eq, overlap, overlap_rate)
                                             : normal_law<false>(p, m_eff, r_eq, overlap, overlap_rate);
  if (p.clip_attractive) f.fn = clip_attractive(f.fn);
  return f;
}

// Elastic energy of the normal spring at this overlap [J] (the dashpot stores none): k_n h^2 / 2
// for the linear family; for Hertz the integral of F_e = (E~/3) sqrt(2 R_eq) h^(3/2),
// (2/15) E~ sqrt(2 R_eq) h^(5/2). 0 when apart.
inline double normal_elastic_energy(const ContactParams& p, double m_eff, double r_eq, double overlap) {
  if (!(overlap > 0)) return 0.0;
  if (p.law == NormalLaw::kHertz) return 2.0 / 15.0 * p.e_tilde * std::sqrt(2.0 * r_eq) * std::pow(overlap, 2.5);
  return 0.5 * linear_coeffs(p, m_eff).k * overlap * overlap;
}

// The overlap at which the elastic force holds a static load `force` [m]: force / k_n, Hertz's
// (force / k_h)^(2/3).
inline double static_overlap(const ContactParams& p, double m_eff, double r_eq, double force) {
  if (p.law == NormalLaw::kHertz) return std::pow(force / hertz_coefficient(p.e_tilde, r_eq), 2.0 / 3.0);
  return force / linear_coeffs(p, m_eff).k;
}

// Normal stiffness dF/dh at this overlap (Hertz: K_N = (E~/2) sqrt(2 R_eq h)), of which the
// tangential spring takes kt_over_kn.
inline double normal_stiffness(const ContactParams& p, double m_eff, double r_eq, double overlap) {
  if (p.law == NormalLaw::kHertz) return 0.5 * p.e_tilde * std::sqrt(2.0 * r_eq * std::max(overlap, 0.0));
  return linear_coeffs(p, m_eff).k;
}

// Tangential elastic-perfectly-plastic spring capped by Coulomb friction (Peyneau 2009 eq.
// 1.25; the history form of LAMMPS gran/*/history and Cundall & Strack 1979), with an optional
// dashpot c_t in parallel with the spring:
//   xi += v_t dt;  xi -= (xi . n) n  (keep the elongation in the tangent plane);
//   F_t = -k_t xi - c_t v_t;
//   if |F_t| > mu |F_n|: F_t *= mu |F_n| / |F_t| and xi = -(F_t + c_t v_t) / k_t (slip),
// so that the spring holds what the cap leaves to it (without the dashpot, xi is scaled as F_t).
// `xi` is the per-contact history, `vt` the tangential relative velocity at the contact point;
// F_t (force on i) goes to `ft`.
//
// On plain arrays and without branches: both sides of each choice are computed, then one is
// selected, so that a loop over many contacts vectorizes (sticking and sliding contacts mix in
// no predictable order, which would defeat a branch anyway). The quotients of the unselected
// sides may be inf or NaN; they are discarded. Dashpot: c_t may be > 0.
template <int D, bool Dashpot>
inline void tangential_spring(double* xi, const double* n, const double* vt, double dt, double k_t, double mu_fn,
                              double c_t, double* ft) {
  double dot = 0;
  for (int k = 0; k < D; ++k) {
    xi[k] += vt[k] * dt;
    dot += xi[k] * n[k];
  }
  double f2 = 0;
  for (int k = 0; k < D; ++k) {
    xi[k] -= dot * n[k];
    ft[k] = -k_t * xi[k];
    if constexpr (Dashpot) {
      const double damped = ft[k] - c_t * vt[k];
      ft[k] = c_t > 0 ? damped : ft[k];
    }
    f2 += ft[k] * ft[k];
  }
  const bool slip = f2 > mu_fn * mu_fn;
  const double capped = mu_fn / std::sqrt(f2);  // selected only when slipping, then f2 > 0
  const double scale = slip ? capped : 1.0;
  const bool held = Dashpot && (c_t > 0) & (k_t > 0);
  for (int k = 0; k < D; ++k) {
    ft[k] *= scale;
    const double scaled = xi[k] * scale;
    if constexpr (Dashpot) {
      const double limit = -(ft[k] + c_t * vt[k]) / k_t;
      xi[k] = held ? (slip ? limit : xi[k]) : scaled;
    } else {
      xi[k] = scaled;
    }
  }
}

// The same for a vector type (Eigen or SVec); returns F_t.
template <class V>
inline V tangential_force(V& xi, const V& n, const V& vt, double dt, double k_t, double mu_fn, double c_t = 0.0) {
  constexpr int D = V::SizeAtCompileTime;
  double s[D], nn[D], v[D], f[D];
  for (int k = 0; k < D; ++k) {
    s[k] = xi[k];
    nn[k] = n[k];
    v[k] = vt[k];
  }
  if (c_t > 0) tangential_spring<D, true>(s, nn, v, dt, k_t, mu_fn, c_t, f);
  else tangential_spring<D, false>(s, nn, v, dt, k_t, mu_fn, c_t, f);
  V ft;
  for (int k = 0; k < D; ++k) {
    xi[k] = s[k];
    ft[k] = f[k];
  }
  return ft;
}

// Tangential dashpot 2 zeta_t sqrt(m* k_t), none for zeta_t <= 0 (without a branch, so that
// loops over contacts vectorize).
inline double tangential_dashpot(double zeta_t, double m_eff, double k_t) {
  return 2.0 * std::max(zeta_t, 0.0) * std::sqrt(m_eff * k_t);
}

}  // namespace silt::dem
