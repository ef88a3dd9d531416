// `silt check`: the compiled model in words and numbers.
#include <cmath>
#include <sstream>

#include "core/text.hpp"
#include "silt/model.hpp"
#include "silt/observables.hpp"

namespace silt {

const char* normal_law_name(NormalLaw law) {
  switch (law) {
    case NormalLaw::kSpringDashpot: return "spring_dashpot (Izard 2014 eq. 3.13-3.17)";
    case NormalLaw::kHooke: return "hooke (LAMMPS gran/hooke, dashpot m* gamma_n)";
    case NormalLaw::kHertz: return "hertz (Peyneau 2009 eq. 1.22, 3.3)";
    case NormalLaw::kLinear: return "linear (Peyneau 2009 eq. 1.23)";
  }
  return "?";
}

std::string describe(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  const char* ax = "xyz";
  o << "scene        " << (m.scene_name.empty() ? m.scene_file : m.scene_name) << "\n";
  o << "dimension    " << m.dim << (m.dim == 2 ? " (disks)" : " (spheres)") << "\n";
  o << "grains       " << m.n_grains << " (" << m.n_grains - m.n_frozen << " free, " << m.n_frozen << " frozen) in "
    << m.group_names.size() << " group(s)\n";
  o << "radii        " << m.r_min << " .. " << m.r_max << " (mean " << m.r_mean << ")\n";
  o << "box          ";
  for (int k = 0; k < m.dim; ++k)
    o << ax[k] << " [" << m.box.lo[k] << ", " << m.box.lo[k] + m.box.len[k] << ")" << (m.box.periodic[k] ? " periodic" : "")
      << (k + 1 < m.dim ? ", " : "\n");
  if (m.box_control.on) {
    o << "box control  pressure " << m.box_control.pressure << " Pa on";
    for (int k = 0; k < m.dim; ++k)
      if (m.box_control.controlled[k]) o << " L" << ax[k];
    o << ", box mass " << m.box_control.mass << " kg\n";
  }
  if (m.shear.on) {
    o << "shear        Lees-Edwards, flow along x, gradient along y; ";
    if (m.shear.stress_controlled) o << "imposed shear stress " << m.shear.stress << " Pa (eq. 3.12)\n";
    else o << "imposed rate gammadot = " << m.shear.rate << " 1/s\n";
  }
  if (m.prepare.compress)
    o << "prepare      isotropic compression at " << m.box_control.pressure << " Pa until static (at most "
      << m.prepare.max_steps << " steps)\n";
  o << "walls        " << m.walls.size() << "\n";
  o << "gravity      (";
  for (int k = 0; k < m.dim; ++k) o << m.gravity[k] << (k + 1 < m.dim ? ", " : ")\n");
  o << "contact      " << normal_law_name(m.contact.law) << "\n";
  o << "friction     mu = " << m.contact.friction << ", k_t/k_n = " << m.contact.kt_ratio
    << (m.contact.friction > 0 ? "" : " (frictionless: no tangential stage work)") << "\n";
  const double zeta = m.zeta_max;
  const double e_pair = zeta < 1 ? std::exp(-3.14159265358979323846 * zeta / std::sqrt(1 - zeta * zeta)) : 0.0;
  o << "time         t_c = " << m.t_contact << " s ("
    << (m.contact.law == NormalLaw::kSpringDashpot ? "given" : "elastic, pi sqrt(m*/k)") << "; lightest pair m* = "
    << m.m_eff_min << " kg, damping ratio " << zeta << ", restitution " << e_pair << ")\n";
  o << "             dt = " << m.dt << " s = t_c/" << m.t_contact / m.dt << "; stability limit " << m.dt_stable
    << " s for one contact (dt/limit = " << m.dt / m.dt_stable << ")\n";
  o << "             a grain held by z contacts is stable below about limit/sqrt(z): "
    << m.dt_stable / std::sqrt(6.0) << " s at z = 6\n";
  if (m.dt > 0.1 * m.t_contact)
    o << "             warning: fewer than 10 steps per contact; collisions are poorly resolved\n";
  o << "run          " << m.run_steps << " steps = " << m.run_steps * m.dt << " s"
    << (m.until_static.on ? ", or until static" : "") << "\n";
  o << "neighbours   skin " << m.skin << " (" << m.skin / m.a_max << " largest diameter); contact candidates "
    << (m.contact_skin < m.skin ? "within a gap of " + format_number(m.contact_skin, 4) : std::string("every listed pair"))
    << "\n";
  // Dimensionless groups.
  const double g = m.gravity.norm();
  if (g > 0) {
    // Stiffness relative to a grain's weight: overlap under its own weight / radius.
    const double mg = m.m_mean * g;
    o << "groups       weight overlap m g / (k_n r) = " << mg / (m.k_max * m.r_mean) << "\n";
  }
  if (m.box_control.on) {
    const double P = m.box_control.pressure;
    const double a = m.a_max;
    o << "groups       kappa = " << (m.contact.law == NormalLaw::kHertz ? "(E~/P)^(2/3)" : "k_n / (a^(d-2) P)") << " = "
      << stiffness_number(m, P) << (m.contact.law == NormalLaw::kHertz ? " (Peyneau eq. 1.31)\n" : " (Peyneau eq. 1.33)\n");
    o << "             zeta = " << m.zeta_max << " (damping ratio of the lightest pair)\n";
    o << "             inertial time sqrt(m / (a^(d-2) P)) = " << std::sqrt(m.m_mean / (std::pow(a, m.dim - 2) * P)) << " s\n";
    if (m.shear.on && !m.shear.stress_controlled) {
      const double I = inertial_number(m, m.shear.rate, P);
      o << "             I = gammadot sqrt(m / (a^(d-2) P)) = " << I << " (Peyneau eq. 1.30); " << 1.0 / (m.shear.rate * m.dt)
        << " steps per unit strain\n";
    }
  }
  o << "observe      ";
  for (size_t k = 0; k < m.observe.size(); ++k) o << m.observe[k] << (k + 1 < m.observe.size() ? ", " : "");
  o << " every " << m.sample_every << " steps\n";
  return o.str();
}

}  // namespace silt
