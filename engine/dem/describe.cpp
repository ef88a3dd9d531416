// The DEM's part of `silt check`: grains, walls, contact law, time step, neighbour search.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "dem/contact_laws.hpp"
#include "dem/contact_setup.hpp"
#include "dem/module.hpp"
#include "silt/text.hpp"

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

// The same collision as the run integrates it: velocity Verlet at the step dt, the force at the new
// overlap and the half-step velocity (dem/integrate.cpp), the contact starting at the beginning of
// a step. Heavily damped, its restitution departs from the law's: e = 0.001 asked gave 3.7e-8 at
// dt = t_c / 50, which `check` did not say. Returns -1 as binary_restitution does.
double stepped_restitution(const ContactParams& p, double m_eff, double r_eq, double v, double dt) {
  double h = 0, hd = v, a = 0;
  for (int64_t k = 0; k < 1000000; ++k) {
    const double half = hd + 0.5 * dt * a;
    h += dt * half;
    if (h <= 0) return -half / v;
    a = -dem::normal_force(p, m_eff, r_eq, h, half).fn / m_eff;
    hd = half + 0.5 * dt * a;
  }
  return -1;
}

// The restitution of the pair of t_c, as `check` prints it.
std::string restitution_text(const Model& m) {
  const Model::ContactTimePair& pair = m.tc_pair;
  const ContactParams& c = pair.law;
  // (Hertz: at the speed whose undamped collision reaches the reference overlap, where t_c is quoted)
  const double v =
      c.law == NormalLaw::kHertz ? dem::hertz_speed_to(c, pair.m_eff, pair.r_eq, c.hertz_ref_overlap * pair.r_eq) : 1.0;
  const double e = binary_restitution(c, pair.m_eff, pair.r_eq, v, m.t_contact);
  const std::string how = c.law == NormalLaw::kHertz ? ", any impact speed" : "";
  std::string text = e < 0 ? "restitution 0 (the dashpot holds the grains until the overlap vanishes" + how + ")"
                           : "restitution " + format_number(e, 4) + " (one collision integrated" + how + ")";
  // At the run's step, where it differs from the law's by more than 2 % of the larger.
  if (!(m.dt > 0) || m.velocities_solved) return text;
  const double stepped = stepped_restitution(c, pair.m_eff, pair.r_eq, v, m.dt);
  const double law = std::max(e, 0.0), at_dt = std::max(stepped, 0.0);
  if (std::abs(at_dt - law) > std::max(0.02 * std::max(law, at_dt), 1e-9))
    text += "; " + format_number(at_dt, 4) + " at this time step (dt = t_c/" + format_number(m.t_contact / m.dt, 4) +
            ": a smaller one comes closer)";
  return text;
}

// A group as check names it: "grains[1] (\"big\")", or "grains[1]" without a name of its own.
std::string group_name(const Model& m, int g) {
  const std::string index = std::to_string(g);
  const bool named = static_cast<size_t>(g) < m.group_names.size() && m.group_names[g] != "group" + index;
  return "grains[" + index + "]" + (named ? " (" + toml_quoted(m.group_names[g]) + ")" : "");
}

// The grains' friction: the scene's, or the range over the pairs of groups that can touch, where
// groups have frictions of their own.
std::string friction_text(const Model& m) {
  double lo = m.contact.friction, hi = lo;
  bool seen = false;
  for (size_t q = 0; q < m.pair_contact.size(); ++q) {
    if (q < m.pair_meets.size() && !m.pair_meets[q]) continue;
    const double f = m.pair_contact[q].friction;
    lo = seen ? std::min(lo, f) : f;
    hi = seen ? std::max(hi, f) : f;
    seen = true;
  }
  std::string text = lo == hi ? "mu = " + format_number(lo, 5)
                              : "mu = " + format_number(lo, 5) + " to " + format_number(hi, 5) +
                                    " by pair of groups (the smaller of the two groups')";
  // The walls' (a wall's own friction, else the grain's group's): a group's 0.5 on a wall was
  // taken while `check` said the scene's 0.05.
  if (m.wall_contact.empty()) return text;
  double wlo = m.wall_contact[0].friction, whi = wlo;
  for (const ContactParams& w : m.wall_contact) {
    wlo = std::min(wlo, w.friction);
    whi = std::max(whi, w.friction);
  }
  if (wlo == lo && whi == hi) return text;
  return text + "; on the walls mu = " + format_number(wlo, 5) + (wlo == whi ? "" : " to " + format_number(whi, 5));
}

}  // namespace

}  // namespace silt

namespace silt::dem {

std::string describe_dem(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  o << "grains       " << m.n_grains << " (" << m.n_grains - m.n_frozen << " free, " << m.n_frozen << " frozen) in "
    << m.group_names.size() << " group(s)\n";
  o << "radii        " << m.r_min << " .. " << m.r_max << " (mean " << m.r_mean << ")\n";
  o << "walls        " << m.walls.size() << "\n";
  o << "contact      " << normal_law_name(m.contact.law) << "\n";
  bool wall_friction = false;
  for (const ContactParams& w : m.wall_contact) wall_friction = wall_friction || w.friction > 0;
  o << "friction     " << friction_text(m) << ", k_t/k_n = " << m.contact.kt_ratio
    << (m.pair_friction() ? ""
        : wall_friction   ? " (frictionless between grains; the walls' friction acts)"
                          : " (frictionless: no tangential stage work)")
    << "\n";
  const bool hertz = m.contact.law == NormalLaw::kHertz;
  const char* tc_meaning =
      m.contact.law == NormalLaw::kSpringDashpot
          ? "given"
          : (hertz ? "duration of an undamped collision reaching contact.hertz_ref_overlap" : "elastic, pi sqrt(m*/k)");
  // A damping ratio of exactly zero prints as 0, not -0 (e = 1 gives -ln(1) = -0).
  const double zeta = m.zeta_max == 0 ? 0.0 : m.zeta_max;
  const std::string s = m.unit("s");
  // (a paste printed "damping ratio 0.98, restitution 1": the ratio of the scene's dashpots, which
  // only its dry preparation keeps, beside the paste's contacts' collision, without them)
  const std::string damping = m.velocities_solved
                                  ? "damping ratio " + format_number(zeta, 5) +
                                        " in the dry preparation; the paste's contacts have no "
                                        "dashpot (the liquid dissipates)"
                                  : "damping ratio " + format_number(zeta, 5) + ", " + restitution_text(m);
  const Model::ContactTimePair& pair = m.tc_pair;
  const std::string groups = pair.wall >= 0 ? std::string(m.pairs_form() ? "" : "no two grains can touch; ") +
                                                  "shortest collision: " + group_name(m, pair.group_i) + " on walls[" +
                                                  std::to_string(pair.wall) + "], its lightest grain"
                             : pair.group_i < 0 ? "lightest pair"
                                                : "shortest collision: " + group_name(m, pair.group_i) + " on " +
                                                      group_name(m, pair.group_j) + ", their lightest pair";
  o << "time         t_c = " << m.t_contact << s << " (" << tc_meaning << "; " << groups << " m* = " << pair.m_eff
    << m.unit("kg") << ", " << damping << ")\n";
  // (where a module solves the velocities, the DEM's step is its dry preparation's alone)
  o << "             dt = " << m.dt << s << " = t_c/" << m.t_contact / m.dt
    << (m.velocities_solved ? " in the dry preparation" : "") << "; stability limit " << m.dt_stable << s
    << " for one contact" << (m.dt_stable_tangential ? ", its tangential spring" : "")
    << " (dt/limit = " << m.dt / m.dt_stable << ")\n";
  o << "             a grain held by z contacts is stable below about limit/sqrt(z): " << m.dt_stable / std::sqrt(6.0)
    << s << " at z = 6\n";
  if (m.dt > 0.1 * m.t_contact)
    o << "             warning: fewer than 10 steps per contact; collisions are poorly resolved\n";
  o << "neighbours   skin " << m.skin << " (" << m.skin / m.a_max << " largest diameter); contact candidates "
    << (m.contact_skin < m.skin ? "within a gap of " + format_number(m.contact_skin, 4)
                                : std::string("every listed pair"))
    << "\n";
  const double g = m.gravity.norm();
  // (of grains on grains: where none can touch, a grain on a wall is check_weight's, whose law may
  // be the grain's own; the line gave [contact]'s for a group of its own modulus, 21 times off)
  if (g > 0 && m.pairs_form()) {
    // Stiffness relative to a grain's weight: overlap under its own weight / radius, of a mean
    // grain on a like one and the softest pair of groups (the stiffest's, 1e-4 where the soft
    // group's was 1e-3, was read as every grain's). Hertz by its own law: m g over the stiffest
    // contact's stiffness at the largest allowed overlap was 25 times below it for spheres of 1 mm
    // and 10 MPa.
    const double mg = m.m_mean * g;
    const char* softest = m.kappa_stiffness_min < m.kappa_stiffness_max
                              ? " (a grain of mean mass and radius on a like one, the softest pair's law)"
                              : " (a grain of mean mass and radius on a like one)";
    if (m.contact.law == NormalLaw::kHertz) {
      ContactParams p = m.contact;
      p.e_tilde = m.kappa_stiffness_min;
      o << "groups       weight overlap (m g / k_h)^(2/3) / r = " << static_overlap(p, 0, m.r_mean, mg) / m.r_mean
        << softest << "\n";
    } else {
      o << "groups       weight overlap m g / (k_n r) = "
        << mg / (m.k_max * (m.kappa_stiffness_min / m.kappa_stiffness_max) * m.r_mean) << softest << "\n";
    }
  }
  return o.str();
}

}  // namespace silt::dem
