// Stress-controlled box lengths, Peyneau (2009) eq. 3.11:
//   M d2L_a/dt2 = (Omega / L_a) (sigma_aa - Sigma_aa),
//   Omega sigma_aa = sum_i m_i v_ia^2 + sum_contacts f_ij,a d_ij,a   (compression positive),
// so a contact pressure below the target shrinks the box. This stage computes sigma_aa after
// the forces of the new step and applies the second half kick of dL/dt; the first half kick and
// the drift are in kick_drift. Sums run over fixed chunks in order: thread-count independent.
#include "core/parallel.hpp"
#include "dem/box_geometry.hpp"
#include "dem/stages.hpp"

namespace silt::dem {
namespace {

template <int D>
void stress_dim(const Model& m, State& s) {
  const PeriodicImage<D> img(s.box);
  double vol = 1;
  for (int k = 0; k < D; ++k) vol *= s.box.len[k];
  for (int a = 0; a < D; ++a) {
    if (!m.box_control.controlled[a]) continue;
    const double sum = deterministic_sum(s.n, 2048, [&](int64_t b, int64_t e) {
      double acc = 0;
      for (int64_t i = b; i < e; ++i) {
        if (!s.particle_frozen[i]) {
          const double va = s.particle_v[D * i + a];
          acc += va * va / s.particle_inv_m[i];
        }
        for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
          const double fa = s.pair_f[D * p + a];
          if (fa == 0.0) continue;
          Vec<D> d = at<D>(s.particle_x.data(), i) - at<D>(s.particle_x.data(), s.pair_j[p]);
          img.apply(d);
          acc += fa * d[a];
        }
      }
      return acc;
    });
    s.box_stress[a] = sum / vol;
  }
}

template <int D>
void kick_dim(const Model& m, State& s) {
  stress_dim<D>(m, s);
  double vol = 1;
  for (int k = 0; k < D; ++k) vol *= s.box.len[k];
  const double h = 0.5 * s.dt;
  for (int a = 0; a < D; ++a)
    if (m.box_control.controlled[a])
      s.box_rate[a] += h * (vol / s.box.len[a]) * (s.box_stress[a] - m.box_control.pressure) / m.box_control.mass;
}

}  // namespace

void box_stress(const Model& m, State& s) {
  if (m.dim == 2) stress_dim<2>(m, s);
  else stress_dim<3>(m, s);
}

void box_kick(const Model& m, State& s) {
  if (m.dim == 2) kick_dim<2>(m, s);
  else kick_dim<3>(m, s);
}

}  // namespace silt::dem
