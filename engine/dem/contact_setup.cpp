#include "dem/contact_setup.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dem/contact_laws.hpp"
#include "silt/text.hpp"

namespace silt {

double verlet_stability_limit(double w0, double zeta) { return 2.0 / w0 * (std::sqrt(1.0 + zeta * zeta) - zeta); }

}  // namespace silt

namespace silt::dem {

void read_contact_law(const SceneDesc& d, Model& m) {
  ContactParams& c = m.contact;
  const std::string model = d.string("contact.model");
  if (model == "spring_dashpot") {
    c.law = NormalLaw::kSpringDashpot;
    c.restitution = d.real("contact.restitution");
    c.contact_time_given = d.real("contact.contact_time");
    const LinearCoeffs per_mass = spring_dashpot_rates(c.restitution, c.contact_time_given);
    c.k1 = per_mass.k;  // Izard eq. 3.17 divided by m*
    c.c1 = per_mass.c;  // Izard eq. 3.16 divided by m*
  } else if (model == "hooke") {
    c.law = NormalLaw::kHooke;
    c.k0 = d.real("contact.k_n");
    c.c1 = d.real("contact.gamma_n");
  } else if (model == "hertz") {
    c.law = NormalLaw::kHertz;
    const double nu = d.real("contact.poisson_ratio");
    c.e_tilde = d.real("contact.young_modulus") / (1.0 - nu * nu);
    c.zeta = d.real("contact.damping");
    c.hertz_ref_overlap = d.real("contact.hertz_ref_overlap");
    if (m.dim == 2) d.fail("contact.model", "hertz is the 3D sphere law; 2D disks use 'linear' (Peyneau eq. 1.23)");
  } else {
    c.law = NormalLaw::kLinear;
    c.k0 = d.real("contact.k_n");
    c.zeta = d.real("contact.damping");
  }
  c.clip_attractive = d.boolean("contact.clip_attractive");
  c.friction = d.real("contact.friction");
  c.kt_ratio = d.real("contact.kt_over_kn");
  c.zeta_t = d.real("contact.tangential_damping");
}

double contact_time(const ContactParams& p, double m_eff, double r_eq, double max_overlap) {
  if (p.law == NormalLaw::kHertz) {
    // Undamped Hertz collision reaching overlap h_m: 1/2 m* v^2 = (2/5) k_h h_m^(5/2) with
    // F = k_h h^(3/2), k_h = (E~/3) sqrt(2 R_eq); duration kHertzDuration (m*/k_h)^(2/5) v^(-1/5)
    // (Johnson 1985, sec. 11.4; contact_laws.hpp).
    const double kh = p.e_tilde / 3.0 * std::sqrt(2.0 * r_eq);
    const double v = std::sqrt(0.8 * kh * std::pow(max_overlap, 2.5) / m_eff);
    return hertz_duration() * std::pow(m_eff / kh, 0.4) * std::pow(v, -0.2);
  }
  if (p.law == NormalLaw::kSpringDashpot) return p.contact_time_given;
  // Damping-ratio laws: the elastic (undamped) contact time pi / w0. It is the time unit of
  // run.dt_over_tc: the damped duration grows without bound as zeta -> 1 and would allow steps
  // near the stability limit.
  const dem::LinearCoeffs kc = dem::linear_coeffs(p, m_eff);
  return std::numbers::pi / std::sqrt(kc.k / m_eff);
}

void derive_contact_scales(const SceneDesc& d, Model& m) {
  // Lightest pair: the two lightest free grains, or one free grain against a wall or a frozen
  // grain (m* = m) when it is alone.
  std::vector<double> free_mass;
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i]) free_mass.push_back(m.init.mass[i]);
  if (free_mass.empty()) free_mass.push_back(m.init.mass[0]);
  std::partial_sort(free_mass.begin(), free_mass.begin() + std::min<size_t>(2, free_mass.size()), free_mass.end());
  m.m_eff_min = free_mass.size() >= 2 ? free_mass[0] * free_mass[1] / (free_mass[0] + free_mass[1]) : free_mass[0];
  const ContactParams& c = m.contact;
  const double r_eq = m.r_min;  // reduced radius of two of the smallest grains
  double zeta = 0;
  if (c.law == NormalLaw::kHertz) {
    // Quoted at the reference overlap; stability checked at the largest allowed overlap.
    m.t_contact = contact_time(c, m.m_eff_min, r_eq, c.hertz_ref_overlap * r_eq);
    m.k_max = 0.5 * c.e_tilde * std::sqrt(2.0 * r_eq * m.limits.max_overlap * m.r_min);
    zeta = c.zeta;
  } else {
    const dem::LinearCoeffs kc = dem::linear_coeffs(c, m.m_eff_min);
    m.t_contact = contact_time(c, m.m_eff_min, r_eq, 0);
    m.k_max = kc.k;
    zeta = kc.c / (2.0 * std::sqrt(kc.k * m.m_eff_min));
  }
  m.zeta_max = zeta;
  m.dt_stable = verlet_stability_limit(std::sqrt(m.k_max / m.m_eff_min), zeta);
  // Other materials (dem/materials.hpp): the stiffest of their laws with the lightest grains, a
  // grain against a wall (m* = m, R_eq = 2 r) included, may lower the limit; t_c stays the scene
  // material's (the unit of run.dt_over_tc).
  auto limit_of = [&](const ContactParams& p, double m_eff, double req) {
    double k = 0, z = 0;
    if (p.law == NormalLaw::kHertz) {
      k = 0.5 * p.e_tilde * std::sqrt(2.0 * req * m.limits.max_overlap * m.r_min);
      z = p.zeta;
    } else {
      const LinearCoeffs kc = linear_coeffs(p, m_eff);
      k = kc.k;
      z = kc.c / (2.0 * std::sqrt(kc.k * m_eff));
    }
    if (verlet_stability_limit(std::sqrt(k / m_eff), z) < m.dt_stable) {
      m.dt_stable = verlet_stability_limit(std::sqrt(k / m_eff), z);
      m.k_max = k;
      m.zeta_max = z;
    }
  };
  for (const ContactParams& p : m.pair_contact) limit_of(p, m.m_eff_min, r_eq);
  const double m_free = free_mass[0];  // the lightest free grain against a wall
  for (const ContactParams& p : m.wall_contact) limit_of(p, m_free, 2.0 * m.r_min);
  // Numbers at the ends of the doubles' range (a tiny radius, a huge modulus) can make these 0,
  // infinite or NaN: a scene that cannot be integrated.
  for (const auto& [name, value] :
       {std::pair{"contact time", m.t_contact}, std::pair{"stiffness", m.k_max},
        std::pair{"stability limit of the time step", m.dt_stable}, std::pair{"reduced mass", m.m_eff_min}})
    if (!(value > 0) || !std::isfinite(value))
      d.fail("contact.model", std::string("the contacts' ") + name + " is " + format_number(value) +
                                  " with these grains and this law: it must be finite and positive (check the radii, "
                                  "densities and the law's parameters)");
}

}  // namespace silt::dem
