#include "paste/contact_stiffness.hpp"

#include <cmath>

#include "dem/contact_laws.hpp"

namespace silt::paste {

void set_contact_stiffness(const Model& m, const State& s, double dt, Links& links) {
  const int D = s.dim;
  const int64_t groups = static_cast<int64_t>(m.materials.size());
  for (size_t k = 0; k < links.c.size(); ++k) {
    Connection& c = links.c[k];
    c.k_n = c.k_t = 0;
    const double ri = s.particle_r[c.i], rj = s.particle_r[c.j];
    const double dist = std::sqrt(c.r[0] * c.r[0] + c.r[1] * c.r[1] + c.r[2] * c.r[2]);
    const double overlap = ri + rj - dist;
    if (!(overlap > 0)) continue;
    const ContactParams& cp =
        m.pair_contact.empty() ? m.contact : m.pair_contact[s.particle_group[c.i] * groups + s.particle_group[c.j]];
    const double m_eff = 1.0 / (s.particle_inv_m[c.i] + s.particle_inv_m[c.j]);
    const double r_eq = dem::reduced_radius(ri, rj);
    const double kn = dem::normal_stiffness(cp, m_eff, r_eq, overlap);
    c.k_n = dt * kn;
    // The spring sticks while below the Coulomb limit; contact_forces left a sliding one at it.
    const double f_n = dem::normal_force(cp, m_eff, r_eq, overlap, 0.0).fn;  // the paste's contacts have no dashpot
    const double kt = cp.kt_ratio * kn;
    const double* hist = &s.pair_hist[static_cast<size_t>(D) * links.pair[k]];
    double spring = 0;
    for (int a = 0; a < D; ++a) spring += hist[a] * hist[a];
    if (kt * std::sqrt(spring) < cp.friction * f_n * (1 - 1e-9)) c.k_t = dt * kt;
  }
}

}  // namespace silt::paste
