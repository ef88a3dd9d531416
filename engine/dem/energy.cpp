// Kinetic energy of the grains, and the runaway check on it.
#include <cmath>

#include "dem/contact_laws.hpp"
#include "dem/stages.hpp"
#include "silt/periodic_image.hpp"

namespace silt::dem {
namespace {

template <int D>
KineticEnergy kinetic_energy_dim(const State& s) {
  constexpr int R = kRotDim<D>;
  KineticEnergy e;
  for (int64_t i = 0; i < s.n; ++i) {
    if (s.particle_frozen[i]) continue;
    const double mass = 1.0 / s.particle_inv_m[i];
    e.total += 0.5 * mass * at<D>(s.particle_v.data(), i).squaredNorm();
    double w2 = 0;
    for (int k = 0; k < R; ++k) w2 += s.particle_w[R * i + k] * s.particle_w[R * i + k];
    const double erot = 0.5 * w2 / s.particle_inv_i[i];
    e.rot += erot;
    e.total += erot;
  }
  return e;
}

// Normal and tangential springs of every grain-grain and grain-wall contact, each under the law
// its force has (dem/materials.hpp: the pair's groups, the wall and the grain's group).
template <int D>
double contact_energy_dim(const Model& m, const State& s) {
  const PeriodicImage<D> img(s.box);
  const int64_t groups = static_cast<int64_t>(m.materials.size());
  double e = 0;
  auto spring = [&](const ContactParams& cp, double kn, const double* xi) {
    double x2 = 0;
    for (int k = 0; k < D; ++k) x2 += xi[k] * xi[k];
    return 0.5 * cp.kt_ratio * kn * x2;
  };
  for (int64_t i = 0; i < s.n; ++i) {
    const double ri = s.particle_r[i];
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      const int64_t j = s.pair_j[p];
      Vec<D> d = at<D>(s.particle_x.data(), i) - at<D>(s.particle_x.data(), j);
      img.apply(d);
      const double overlap = ri + s.particle_r[j] - d.norm();
      if (!(overlap > 0)) continue;
      const ContactParams& cp =
          m.pair_contact.empty() ? m.contact : m.pair_contact[s.particle_group[i] * groups + s.particle_group[j]];
      const double m_eff = 1.0 / (s.particle_inv_m[i] + s.particle_inv_m[j]);
      const double r_eq = reduced_radius(ri, s.particle_r[j]);
      e += normal_elastic_energy(cp, m_eff, r_eq, overlap);
      e += spring(cp, normal_stiffness(cp, m_eff, r_eq, overlap), &s.pair_hist[D * p]);
    }
    if (s.particle_frozen[i]) continue;
    for (int w = 0; w < s.n_walls; ++w) {
      const double overlap = -m.walls[w].gap<D>(at<D>(s.particle_x.data(), i), ri);
      if (!(overlap > 0)) continue;
      const ContactParams& cp = m.wall_contact[w * groups + s.particle_group[i]];
      const double m_eff = 1.0 / s.particle_inv_m[i];
      e += normal_elastic_energy(cp, m_eff, 2.0 * ri, overlap);
      e += spring(cp, normal_stiffness(cp, m_eff, 2.0 * ri, overlap), &s.wall_hist[D * (i * s.n_walls + w)]);
    }
  }
  return e;
}

}  // namespace

double contact_energy(const Model& m, const State& s) {
  return s.dim == 2 ? contact_energy_dim<2>(m, s) : contact_energy_dim<3>(m, s);
}

KineticEnergy kinetic_energy(const State& s) {
  return s.dim == 2 ? kinetic_energy_dim<2>(s) : kinetic_energy_dim<3>(s);
}

void energy_check(const Model& m, State& s) {
  if ((s.step + 1) % m.limits.check_every != 0) return;
  const double ke = kinetic_energy(s).total;
  if (!std::isfinite(ke) || ke > m.limits.energy_factor * m.limits.energy_supply(s.t + s.dt))
    s.events[event::kRunaway].raise(0, ke);
}

}  // namespace silt::dem
