// `silt check`: the compiled model in words and numbers.
#include <cmath>
#include <sstream>

#include "core/text.hpp"
#include "dem/contact_laws.hpp"
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

namespace {

// Restitution of one head-on collision of two grains of reduced mass m_eff and reduced radius
// r_eq under the scene's normal law (clipping included): m* h'' = -F_n(h, h') from h = 0 at the
// impact speed v, integrated by RK4 in steps of a 2000th of the undamped contact time until the
// overlap closes; e = -h'/v then. Returns -1 when the overlap has not closed after 50 contact
// times: a dashpot near critical damping that may pull (no clipping) holds the grains while the
// overlap decays as a power of time, so they part with no speed (e = 0 in the limit).
// For the linear laws this is exp(-pi zeta / sqrt(1 - zeta^2)) without clipping; for Hertz with
// the dashpot 2 zeta sqrt(m* K_N) it does not depend on v (Peyneau 2009 sec. 3.1.1).
double binary_restitution(const ContactParams& p, double m_eff, double r_eq, double v, double t_elastic) {
  auto accel = [&](double h, double hd) { return -dem::normal_force(p, m_eff, r_eq, h, hd).fn / m_eff; };
  const double dt = t_elastic / 2000;
  double h = 0, hd = v;
  for (int64_t k = 0; k < 100000; ++k) {
    // RK4 on (h, h'); the force law is evaluated at h >= 0 only (the overlap closes below).
    const double a1 = accel(h, hd);
    const double h2 = h + 0.5 * dt * hd, v2 = hd + 0.5 * dt * a1, a2 = accel(std::max(h2, 0.0), v2);
    const double h3 = h + 0.5 * dt * v2, v3 = hd + 0.5 * dt * a2, a3 = accel(std::max(h3, 0.0), v3);
    const double h4 = h + dt * v3, v4 = hd + dt * a3, a4 = accel(std::max(h4, 0.0), v4);
    h += dt / 6 * (hd + 2 * v2 + 2 * v3 + v4);
    hd += dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    if (h <= 0) return -hd / v;
  }
  return -1;
}

// The restitution of the lightest pair, as `check` prints it.
std::string restitution_text(const Model& m) {
  const ContactParams& c = m.contact;
  const double r_eq = m.r_min;
  double v = 1;
  if (c.law == NormalLaw::kHertz) {
    // The speed whose undamped collision reaches the reference overlap, where t_c is quoted:
    // 1/2 m* v^2 = (2/5) k_h h^(5/2).
    const double kh = c.e_tilde / 3.0 * std::sqrt(2.0 * r_eq), h = c.hertz_ref_overlap * r_eq;
    v = std::sqrt(0.8 * kh * std::pow(h, 2.5) / m.m_eff_min);
  }
  const double e = binary_restitution(c, m.m_eff_min, r_eq, v, m.t_contact);
  const std::string how = c.law == NormalLaw::kHertz ? ", any impact speed" : "";
  if (e < 0) return "restitution 0 (the dashpot holds the grains until the overlap vanishes" + how + ")";
  return "restitution " + format_number(e, 4) + " (one collision integrated" + how + ")";
}

}  // namespace

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
  o << "time         t_c = " << m.t_contact << " s ("
    << (m.contact.law == NormalLaw::kSpringDashpot ? "given" : "elastic, pi sqrt(m*/k)") << "; lightest pair m* = "
    << m.m_eff_min << " kg, damping ratio " << m.zeta_max << ", " << restitution_text(m) << ")\n";
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
    o << "             inertial time sqrt(m / (a^(d-2) P)) = " << std::sqrt(m.m_a / (std::pow(a, m.dim - 2) * P))
      << " s (m = " << m.m_a << " kg, a grain of diameter a = " << a << " m)\n";
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
