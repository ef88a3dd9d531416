// The shear module: box lengths driven by an imposed pressure (Peyneau 2009 eq. 3.11), simple
// shear by Lees-Edwards conditions at imposed rate, inertial number or shear stress (eq. 3.12),
// and the isotropic compression that prepares a packing (procedure O).
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "shear/collisions.hpp"
#include "shear/cycle_origin.hpp"
#include "shear/module.hpp"
#include "shear/stages.hpp"
#include "silt/text.hpp"

namespace silt::shear {
namespace {

std::vector<KeySpec> shear_keys() {
  using K = KeyType;
  using S = std::vector<std::string>;
  // clang-format off
  std::vector<KeySpec> s = {
      // ---- box
      {"box.pressure", K::kReal, std::nullopt, Range::positive(), "Pa", true, {}, "Imposed pressure on the controlled box lengths (Peyneau 2009 eq. 3.11); absent: fixed box."},
      {"box.controlled", K::kBoolList, std::nullopt, Range::any(), "", false, {}, "Which box lengths follow the pressure (default: every periodic one)."},
      {"box.cycle", K::kString, Value(std::string("none")), Range::any(), "", false, S{"none", "alternating", "biaxial"}, "Cyclic imposed stresses (Peyneau 2009 ch. 5): alternating, Sigma_xx = P (1 + d sin wt), Sigma_yy = P (1 - d sin wt); biaxial, Sigma_xx = P, Sigma_yy = P (1 + d (1 - cos wt))."},
      {"box.cycle_amplitude", K::kReal, Value(0.1), Range::open_closed(0, 1), "", true, {}, "d = delta P / P of the cyclic stresses."},
      {"box.cycle_period", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "Period 2 pi / w of the cyclic stresses."},
      {"box.cycle_viscous_number", K::kReal, std::nullopt, Range::positive(), "", true, {}, "Or the viscous number Vi = eta w / P of the cycles (Peyneau eq. 5.7; eta w a / P in 2D, a the largest diameter), with eta = lubrication.viscosity."},
      {"box.mass_factor", K::kReal, Value(1.0), Range::positive(), "", true, {}, "Box mass M in units of the total grain mass N m (Peyneau: M = N m), for the box lengths and a stress-controlled shear."},
      // ---- shear
      {"shear.rate", K::kReal, std::nullopt, Range::any(), "1/s", true, {}, "Imposed shear rate gammadot of the flow v_x = gammadot y (liquid regime)."},
      {"shear.inertial_number", K::kReal, std::nullopt, Range::positive(), "", true, {}, "Imposed inertial number I = gammadot sqrt(m / (a^(d-2) P)) (Peyneau eq. 1.30), with P = box.pressure."},
      {"shear.viscous_number", K::kReal, std::nullopt, Range::positive(), "", true, {}, "Imposed viscous number Vi = eta gammadot / P of a lubricated paste (Peyneau eq. 1.34; eta gammadot a / P in 2D, where P is a force per length and the resistances grow as eta a; a the largest diameter), with eta = lubrication.viscosity and P = box.pressure."},
      {"shear.stress", K::kReal, std::nullopt, Range::any(), "Pa", true, {}, "Imposed shear stress tau = -sigma_xy (solid regime, Peyneau eq. 3.12): gammadot follows it."},
      // ---- prepare
      {"prepare.compress", K::kBool, Value(false), Range::any(), "", false, {}, "Before the run, compress the grains isotropically at box.pressure (every periodic length controlled, no shear) until static: Peyneau's procedure O."},
      {"prepare.pressure", K::kReal, std::nullopt, Range::positive(), "Pa", false, {}, "Pressure of the compression when the run itself has no box.pressure (a box of fixed size sheared at a given rate)."},
      {"prepare.phi", K::kReal, std::nullopt, Range::open_closed(0, 1), "", false, {}, "Stop the compression when the solid fraction reaches this, static or not (a random packing below jamming, its velocities then zeroed)."},
      {"prepare.dilation", K::kReal, Value(1.0), Range::closed(1, 2), "", false, {}, "After the compression, multiply the grains' centres and the box lengths by this: the initial state of a paste, its grains apart (Peyneau 2009 sec. 2.3.1: 1.1)."},
      {"prepare.max_steps", K::kInt, Value(int64_t{2000000}), Range::closed(1, 4.6e18), "", false, {}, "Longest preparation; the run then starts from where it got, with a warning."},
  };
  // clang-format on
  return s;
}

std::vector<KeyRule> shear_rules() {
  return {
      KeyRule::one_of({{"shear.rate"}, {"shear.inertial_number"}, {"shear.viscous_number"}, {"shear.stress"}}),
      KeyRule::one_of({{"box.cycle_period"}, {"box.cycle_viscous_number"}}),
      KeyRule::requires_any("box.controlled", {"box.pressure"}, "only a pressure moves the box lengths"),
      KeyRule::requires_any("box.mass_factor", {"box.pressure", "shear.stress"},
                            "it is the inertia of the controlled lengths and of a stress-controlled shear"),
      KeyRule::requires_any("shear.inertial_number", {"box.pressure"}, "I is relative to the imposed pressure"),
      KeyRule::requires_any("box.cycle", {"box.pressure"}, "the cycles are about the imposed pressure"),
      KeyRule::requires_any("box.cycle_viscous_number", {"lubrication.viscosity"},
                            "Vi is relative to the liquid's viscosity"),
      KeyRule::requires_any("shear.viscous_number", {"box.pressure"}, "Vi is relative to the imposed pressure"),
      KeyRule::requires_any("shear.viscous_number", {"lubrication.viscosity"},
                            "Vi is relative to the liquid's viscosity"),
      KeyRule::requires_any("prepare.compress", {"box.pressure", "prepare.pressure"},
                            "the isotropic compression is at the imposed pressure"),
  };
}

const std::string kNeedsShear = "applies where the scene shears (shear.rate, shear.inertial_number or shear.stress)";

std::vector<ObservableSpec> shear_observables() {
  auto sheared = [](const char* name) {
    return [name](const Model& m, const ObservableArgs&) {
      return m.shear.on ? std::string() : "observable '" + std::string(name) + "' " + kNeedsShear;
    };
  };
  std::vector<ObservableSpec> o = {
      {"gamma", "", "accumulated shear strain",
       [](const ObservableContext& c, const ObservableArgs&) { return c.s.shear_strain; }},
      {"gammadot", "1/s", "shear rate",
       [](const ObservableContext& c, const ObservableArgs&) { return c.s.shear_rate; }},
      {"I", "", "inertial number at the imposed (else the measured sigma_yy) pressure (nan at a pressure <= 0)",
       [](const ObservableContext& c, const ObservableArgs&) {
         const double p = c.m.box_control.on ? c.m.box_control.pressure : c.meas(measure_part::kStress).stress[1][1];
         return p > 0 ? inertial_number(c.m, c.s.shear_rate, p) : std::numeric_limits<double>::quiet_NaN();
       }},
  };
  o.push_back({"cycle", "", "cycles of the imposed stresses done, w t / (2 pi) (the phase, through steered w's)",
               [](const ObservableContext& c, const ObservableArgs&) {
                 return cycle_origin(c.m, c.s).phase(c.s.t) / (2 * std::numbers::pi);
               }});
  o.back().check = [](const Model& m, const ObservableArgs&) {
    return m.box_control.cycle != StressCycle::kNone ? "" : "observable 'cycle' applies where box.cycle is set";
  };
  o[0].check = sheared("gamma");
  o[1].check = sheared("gammadot");
  o[2].check = sheared("I");
  return o;
}

void setup_cycle(const SceneDesc& d, Model& m) {
  BoxControl& b = m.box_control;
  const std::string kind = d.string("box.cycle");
  const bool period = d.has("box.cycle_period"), vi = d.has("box.cycle_viscous_number");
  if (kind == "none") {
    for (const char* k : {"box.cycle_period", "box.cycle_viscous_number", "box.cycle_amplitude"})
      if (d.has(k)) d.fail(k, "applies to cyclic stresses: set box.cycle");
    return;
  }
  if (period == vi) d.fail("box.cycle", "give one of box.cycle_period and box.cycle_viscous_number");
  if (m.dim != 2 && kind == "alternating") d.fail("box.cycle", "the alternating cycle is defined in 2D (x and y)");
  b.cycle = kind == "alternating" ? StressCycle::kAlternating : StressCycle::kBiaxial;
  if (d.boolean("run.stop_when_static"))
    d.fail("run.stop_when_static", "a packing under cyclic stresses (box.cycle) is never at rest: give a run length");
  b.cycle_amplitude = d.real("box.cycle_amplitude");
  b.cycle_omega =
      period ? 2 * std::numbers::pi / d.real("box.cycle_period")
             : d.real("box.cycle_viscous_number") / viscous_time(m, d.real("lubrication.viscosity"), b.pressure);
  for (int k = 0; k < 2; ++k)
    if (!m.box.periodic[k]) d.fail("box.cycle", "cyclic stresses act on the x and y lengths: both must be periodic");
}

void setup_box_control(const SceneDesc& d, Model& m) {
  BoxControl& b = m.box_control;
  double grain_mass = 0;
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i]) grain_mass += m.init.mass[i];
  if (d.has("box.pressure") || d.has("shear.stress") || d.has("prepare.pressure")) {
    b.mass_factor = d.real("box.mass_factor");
    b.mass = b.mass_factor * grain_mass;
  }
  if (!d.has("box.pressure")) return;
  if (m.n_frozen > 0)
    d.fail("box.pressure", "a stress-controlled box cannot hold frozen grains (they would not follow its deformation)");
  b.on = true;
  b.pressure = d.real("box.pressure");
  setup_cycle(d, m);
  std::vector<bool> c(m.box.periodic.begin(), m.box.periodic.begin() + m.dim);
  if (d.has("box.controlled")) c = d.booleans("box.controlled");
  if (static_cast<int>(c.size()) != m.dim) d.fail("box.controlled", "needs " + std::to_string(m.dim) + " entries");
  bool any = false;
  for (int k = 0; k < m.dim; ++k) {
    if (c[k] && !m.box.periodic[k]) d.fail("box.controlled", "only periodic box lengths can follow the pressure");
    b.controlled[k] = c[k];
    any = any || c[k];
  }
  if (!any) d.fail("box.pressure", "box.pressure is set but no box length is controlled (make a direction periodic)");
}

// Lees-Edwards simple shear: flow along x, gradient along y, both periodic.
void setup_shear(const SceneDesc& d, Model& m) {
  ShearControl& sh = m.shear;
  // (one at most: a KeyRule::one_of)
  const std::string key =
      d.first_given({"shear.rate", "shear.inertial_number", "shear.viscous_number", "shear.stress"}, "");
  if (key.empty()) return;
  if (!m.box.periodic[0] || !m.box.periodic[1])
    d.fail(key, "simple shear (Lees-Edwards) needs a domain periodic along x (flow) and y (gradient)");
  if (!m.walls.empty()) d.fail(key, "simple shear by Lees-Edwards conditions has no walls");
  if (m.n_frozen > 0) d.fail(key, "simple shear by Lees-Edwards conditions cannot hold frozen grains");
  sh.on = true;
  m.box.lees_edwards = true;
  if (d.has("shear.rate")) {
    sh.rate = d.real("shear.rate");
  } else if (d.has("shear.inertial_number")) {
    // I is linear in gammadot (Peyneau eq. 1.30): the rate of I = 1, scaled.
    sh.rate = d.real("shear.inertial_number") / inertial_number(m, 1.0, m.box_control.pressure);
  } else if (d.has("shear.viscous_number")) {
    sh.rate = d.real("shear.viscous_number") / viscous_time(m, d.real("lubrication.viscosity"), m.box_control.pressure);
  } else {
    sh.stress_controlled = true;
    sh.stress = d.real("shear.stress");
  }
}

// The box's own oscillation, eq. 3.11 with the grains following its affine strain: the contact
// network's stiffness along a length L is K = z N k <n^4> d^2 / (2 L^2) (N grains, z = 2 D
// contacts each, <n^4> = 3/8 in 2D and 1/5 in 3D for isotropic directions, d = a_max, k a
// contact's stiffness), the box's mass M; velocity-Verlet holds it while dt < 2 sqrt(M / K). A box a
// million times lighter than its grains was taken, and the run failed at step 123 advising
// stiffer contacts (at 1e-300, in the kick, advising a shorter step).
void check_box_mass(const SceneDesc& d, const Model& m) {
  const BoxControl& b = m.box_control;
  if (!(b.on || m.shear.stress_controlled) || m.velocities_solved || m.adaptive_dt) return;
  double len = 1e308;
  for (int k = 0; k < m.dim; ++k)
    if ((b.on && b.controlled[k]) || (m.shear.stress_controlled && k < 2)) len = std::min(len, m.box.len[k]);
  const double n_free = static_cast<double>(m.n_grains - m.n_frozen);
  const double n4 = m.dim == 2 ? 3.0 / 8 : 1.0 / 5;
  const double a_over_len = m.a_max / len;
  // Hertz: k_max, the stiffness at the largest allowed overlap (limits.max_overlap r_min), taken to
  // contact.hertz_ref_overlap r_min, k growing as the overlap's square root (k_max itself was 14
  // times the stiffness of a packing's contacts under shear3d_frictionless's pressure).
  const double k = m.contact.law == NormalLaw::kHertz
                       ? m.k_max * std::sqrt(m.contact.hertz_ref_overlap / m.limits.max_overlap)
                       : m.k_max;
  const double stiffness = m.dim * n_free * k * n4 * a_over_len * a_over_len;
  // Half the estimate's bound: the box couples to the grains' own modes, and a mass just above the
  // estimate's least (pack_2d at 1.01 times it, shear2d_dry at 1.01) ran away within a few hundred
  // steps where twice it held.
  const double limit = std::sqrt(b.mass / stiffness);
  if (!(stiffness > 0) || m.dt <= limit) return;
  const double least = b.mass_factor * (m.dt / limit) * (m.dt / limit);
  d.fail(d.first_given({"box.mass_factor", "box.pressure", "shear.stress"}, "box.mass_factor"),
         "the box of mass " + format_number(b.mass, 4) + m.unit("kg") +
             " (box.mass_factor = " + format_number(b.mass_factor, 4) +
             ") oscillates on its grains' contacts faster than the time step " + format_number(m.dt, 4) + m.unit("s") +
             " can follow (stable below " + format_number(limit, 4) + m.unit("s") +
             "): raise box.mass_factor to at least " + format_number(least, 3) + " or reduce the time step");
}

// A pressure or an imposed shear stress that presses the contacts by more than a diameter: a
// stiffness number below 1 (the deflection is about a / kappa, Peyneau eq. 1.32), where a run fails
// at limits.max_overlap, a fifth of a radius by default. box.pressure = 1e10 on contacts of
// k_n = 1e4 failed at step 1 with a non-finite velocity, advising a shorter step; shear.stress =
// 1e300 at step 1 advising a larger k_n.
void check_stress_against_contacts(const SceneDesc& d, const Model& m, const std::string& key, const char* name,
                                   double signed_stress) {
  const double stress = std::abs(signed_stress);
  if (!(stress > 0)) return;
  const double kappa = stiffness_number(m, stress);
  if (kappa >= 1) return;
  const bool hertz = m.contact.law == NormalLaw::kHertz;
  const double most = hertz ? stress * std::pow(kappa, 1.5) : stress * kappa;
  d.fail(key, std::string(name) + " " + format_number(signed_stress, 4) + m.unit("Pa") +
                  " gives a stiffness number kappa = " + format_number(kappa, 3) +
                  " below 1: it presses each contact by about a / kappa, more than a diameter, where a run fails at "
                  "limits.max_overlap = " +
                  format_number(m.limits.max_overlap, 3) + " of a radius: lower its magnitude (kappa is 1 at " +
                  format_number(most, 4) + m.unit("Pa") +
                  "; packings are run at kappa 1e3 and more) or stiffen the contacts: " +
                  (m.contact.law == NormalLaw::kSpringDashpot ? "shorten " : "raise ") + m.kappa_softest_key);
}

void check_box_pressure(const SceneDesc& d, const Model& m) {
  const double pressure =
      m.box_control.on ? m.box_control.pressure : (m.prepare.compress ? preparation_pressure(m) : 0.0);
  // (a stress cycle presses the contacts hardest at its peak: P (1 + d) alternating, P (1 + 2 d) biaxial)
  const BoxControl& b = m.box_control;
  const bool cycles = b.on && b.cycle != StressCycle::kNone;
  const double peak =
      cycles ? pressure * (1 + (b.cycle == StressCycle::kBiaxial ? 2 : 1) * b.cycle_amplitude) : pressure;
  check_stress_against_contacts(d, m, d.first_given({"box.pressure", "prepare.pressure"}, "box.pressure"),
                                cycles ? "the cycle's largest stress" : "the pressure", peak);
  // Gravity along a periodic length the pressure controls: nothing holds the grains, which fall
  // through the box as a whole, and their fall counts as kinetic pressure (pack_2d under g = 1 grew
  // its box from 19.5 to 177 along y and failed when x shrank below twice the range).
  for (int k = 0; k < m.dim && pressure > 0; ++k)
    if (m.box.periodic[k] && m.gravity[k] != 0 && (!b.on || b.controlled[k]))
      d.fail(d.first_given({"gravity.vector", "gravity.magnitude"}, "gravity.magnitude"),
             "gravity along " + std::string(1, "xyz"[k]) +
                 ", a periodic length the pressure controls: nothing holds the grains, which fall through the box "
                 "as a whole, their fall counted as pressure; give it no component along " +
                 std::string(1, "xyz"[k]));
  if (m.shear.on && m.shear.stress_controlled)
    check_stress_against_contacts(d, m, "shear.stress", "the shear stress", m.shear.stress);
}

// Collisions at the imposed rate that press the grains past limits.max_overlap even at the mean
// speed difference (shear_collision, ratio 1 and more) fail for certain, and are refused; below it
// `check` prints the ratio and a failure explains it (shear2d_dry at I = 10, ratio 0.71, failed at
// step 28 and was told only to stiffen its contacts). The value that brings the ratio to 0.3
// (shear/collisions.cpp) scales with it: the overlap goes as the speed, Hertz's as its 4/5 power.
void check_shear_collisions(const SceneDesc& d, const Model& m) {
  const ShearCollision c = shear_collision(m);
  if (!(c.ratio >= 1)) return;
  const std::string key = d.first_given({"shear.rate", "shear.inertial_number"}, "shear.rate");
  d.fail(key, collision_text(m, c) + ", at which the run fails: lower " + key + " to " +
                  format_number(rate_for(m, std::abs(d.real(key)), c.ratio, 0.3), 3) +
                  ", where they press by 0.3 of it, or make the contacts stiffer (" +
                  stiffer_by(m, m.kappa_softest_key, c.ratio, 0.3) + ")");
}

void check_shear_step(const SceneDesc& d, const Model& m) {
  check_box_pressure(d, m);
  check_box_mass(d, m);
  // With the time step known: an imposed rate that shears the box too far in one step. Neighbours
  // one above the other (centres up to 2 r_max apart along y) stream past each other by
  // gammadot dt 2 r_max a step; beyond limits.max_overlap r_min, one step can press touching grains
  // past the overlap at which the run fails. A fixed step only: an adaptive one (the paste's)
  // starts at 1e-3 of the shear time and follows what changes.
  if (!m.shear.on || m.shear.stress_controlled || m.adaptive_dt) return;
  const double slip = std::abs(m.shear.rate) * m.dt * 2 * m.r_max, most = m.limits.max_overlap * m.r_min;
  if (slip <= most) return check_shear_collisions(d, m);
  const std::string key = d.first_given({"shear.rate", "shear.inertial_number", "shear.viscous_number"}, "shear.rate");
  d.fail(key, "the shear rate " + format_number(m.shear.rate, 4) +
                  " 1/s streams neighbouring grains past each other by " + format_number(slip, 3) +
                  " m in a time step of " + format_number(m.dt, 4) +
                  " s (gammadot dt 2 r_max), more than limits.max_overlap r_min = " + format_number(most, 3) +
                  " m, the overlap at which the run fails: lower the rate below " +
                  format_number(most / (m.dt * 2 * m.r_max), 4) + " 1/s or the time step");
}

void compile_shear(const SceneDesc& d, Model& m) {
  setup_box_control(d, m);
  setup_shear(d, m);
  m.prepare.compress = d.boolean("prepare.compress");
  m.prepare.max_steps = d.integer("prepare.max_steps");
  m.prepare.dilation = d.real("prepare.dilation");
  if (d.has("prepare.pressure")) {
    if (d.has("box.pressure")) d.fail("prepare.pressure", "the compression is at box.pressure: give one of them");
    m.prepare.pressure = d.real("prepare.pressure");
  }
  if (d.has("prepare.phi")) m.prepare.phi = d.real("prepare.phi");
  for (const char* k : {"prepare.pressure", "prepare.phi"})
    if (d.has(k) && !m.prepare.compress) d.fail(k, "applies to the compression: set prepare.compress = true");
  if (m.prepare.dilation != 1 && !m.prepare.compress)
    d.fail("prepare.dilation", "the dilation follows the compression: set prepare.compress = true");
  m.pair_forces_every_step = box_stage_on(m);
}

std::string describe_shear(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  if (m.box_control.on) {
    o << "box control  pressure " << m.box_control.pressure << m.unit("Pa") << " on";
    for (int k = 0; k < m.dim; ++k)
      if (m.box_control.controlled[k])
        o << " L"
          << "xyz"[k];
    // (a paste's box rates are solved with the grains' velocities: no mass; box.mass_factor unused)
    if (m.velocities_solved) o << ", its rates solved with the grains' velocities\n";
    else o << ", box mass " << m.box_control.mass << m.unit("kg") << "\n";
  }
  if (m.shear.on) {
    o << "shear        Lees-Edwards, flow along x, gradient along y; ";
    if (m.shear.stress_controlled) o << "imposed shear stress " << m.shear.stress << m.unit("Pa") << " (eq. 3.12)\n";
    else o << "imposed rate gammadot = " << m.shear.rate << m.unit("1/s") << "\n";
    if (const ShearCollision c = shear_collision(m); c.ratio > 0)
      o << "             neighbours meet at about gammadot 2 r_max = " << c.speed << m.unit("m/s")
        << ": an undamped collision of the heaviest grains presses by " << c.ratio
        << " of limits.max_overlap (sheared runs were seen to fail from 0.5 to 0.9 of it)\n";
  }
  if (m.prepare.compress)
    o << "prepare      isotropic compression at " << preparation_pressure(m) << m.unit("Pa") << " until "
      << (m.prepare.phi > 0 ? "Phi = " + std::to_string(m.prepare.phi) + " or " : std::string()) << "static (at most "
      << m.prepare.max_steps << " steps)\n";
  if (m.box_control.on) {
    const double P = m.box_control.pressure;
    const double a = m.a_max;
    const bool hertz = m.contact.law == NormalLaw::kHertz;
    o << "groups       kappa = " << (hertz ? "(E~/P)^(2/3)" : "k_n / (a^(d-2) P)") << " = "
      << stiffness_number_text(m, P) << (hertz ? " (Peyneau eq. 1.31)\n" : " (Peyneau eq. 1.33)\n");
    o << "             zeta = " << (m.zeta_max == 0 ? 0.0 : m.zeta_max) << " (damping ratio of the lightest pair"
      << (m.tc_pair.group_i >= 0 ? " of the groups of t_c" : "") << ")\n";
    o << "             inertial time sqrt(m / (a^(d-2) P)) = " << std::sqrt(m.m_a / (std::pow(a, m.dim - 2) * P))
      << m.unit("s") << " (m = " << m.m_a << m.unit("kg") << ", a grain of diameter a = " << a << m.unit("m") << ")\n";
    if (m.shear.on && !m.shear.stress_controlled && !m.velocities_solved) {
      const double I = inertial_number(m, m.shear.rate, P);
      o << "             I = gammadot sqrt(m / (a^(d-2) P)) = " << I << " (Peyneau eq. 1.30); "
        << 1.0 / (m.shear.rate * m.dt) << " steps per unit strain\n";
    }
  }
  return o.str();
}

std::string steer_shear(Model& m, const Model& fresh) {
  if (fresh.shear.on != m.shear.on || fresh.shear.stress_controlled != m.shear.stress_controlled)
    return "it would switch the shear on or off, or between imposed rate and imposed stress: set it when stopped";
  m.box_control.pressure = fresh.box_control.pressure;
  m.box_control.mass_factor = fresh.box_control.mass_factor;
  m.box_control.mass = fresh.box_control.mass;
  m.box_control.cycle_amplitude = fresh.box_control.cycle_amplitude;
  // A new w (a period, a viscous number, or the pressure or viscosity it is relative to) goes on
  // from the phase reached, at the next step (cycle_origin_stage).
  m.box_control.cycle_omega = fresh.box_control.cycle_omega;
  m.shear.rate = fresh.shear.rate;
  m.shear.stress = fresh.shear.stress;
  return "";
}

bool shear_enabled(const SceneDesc& d) { return d.has_table("box") || d.has_table("shear") || d.has_table("prepare"); }

}  // namespace

const ModuleSpec& module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "shear";
    s.follows_forces = true;  // the box's stresses
    s.doc = "stress-controlled box lengths, Lees-Edwards simple shear, isotropic compression";
    s.keys = shear_keys();
    s.rules = shear_rules();
    s.observables = shear_observables();
    s.enabled = shear_enabled;
    s.needs_grains = true;
    s.compile = compile_shear;
    s.finish = check_shear_step;
    s.describe = describe_shear;
    s.steer = steer_shear;
    s.fields = {{"box_cycle_origin", Extent::kFree, "",
                 "where the cycles' phase is counted from: empty (w t), or t0, the phase at t0 and the w since "
                 "(silt::CycleOrigin); cycle_origin"}};
    // The origin from the start (w t), or the restored state's own: a w steered before the first
    // step then goes on from the phase reached, not from w_new t.
    s.adopt = [](const Model& m, State& st) {
      if (m.box_control.on && m.box_control.cycle != StressCycle::kNone &&
          st.module_field(cycle_origin_field()).empty())
        st.module_field(cycle_origin_field()) = {0.0, 0.0, m.box_control.cycle_omega};
    };
    s.check_state = [](const Model&, const State& st) -> std::string {
      const size_t n = st.module_field(cycle_origin_field()).size();
      return n == 0 || n == 3 ? "" : "box_cycle_origin has " + std::to_string(n) + " entries, not 0 or 3";
    };
    return s;
  }();
  return spec;
}

}  // namespace silt::shear
