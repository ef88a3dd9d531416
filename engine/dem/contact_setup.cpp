#include "dem/contact_setup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dem/contact_laws.hpp"
#include "dem/grain_setup.hpp"
#include "silt/text.hpp"

namespace silt {

// 2/w0 (sqrt(1 + zeta^2) - zeta), written without the difference that cancels to 0 for a strong
// dashpot.
double verlet_stability_limit(double w0, double zeta) { return 2.0 / w0 / (std::hypot(1.0, zeta) + zeta); }

}  // namespace silt

namespace silt::dem {
namespace {

// [contact]'s spring (k_n) or modulus (young_modulus): what a group or a wall that gives none of
// its own has. Where every group gives its own and every wall its own or is rigid, no contact has
// it and the scene may leave it out; it is then the first group's, so that a scene of one
// material still has [contact]'s law exactly. Else it is required, and the refusal names who
// needs it.
double contact_or_own(const SceneDesc& d, const std::string& own) {
  const std::string key = "contact." + own;
  if (d.has(key)) return d.real(key);
  // A scene without grains is refused for that by setup_grains (it was blamed on contact.k_n),
  // and explicit positions are checked before (check_explicit_positions).
  if (d.group_count("grains") == 0) return 0;
  std::string without;
  auto need = [&](const std::string& prefix, bool may_be_rigid) {
    if (d.has(prefix + own) || (may_be_rigid && d.has(prefix + "rigid") && d.boolean(prefix + "rigid"))) return;
    without += (without.empty() ? "" : ", ") + prefix.substr(0, prefix.size() - 1);
  };
  for (int g = 0; g < d.group_count("grains"); ++g) need("grains[" + std::to_string(g) + "].", false);
  for (int w = 0; w < d.group_count("walls"); ++w) need("walls[" + std::to_string(w) + "].", true);
  if (!without.empty())
    d.fail(key, "missing required key '" + key + "': " + without + " give" +
                    (without.find(',') == std::string::npos ? "s" : "") + " no " + own + " of " +
                    (without.find(',') == std::string::npos ? "its" : "their") + " own");
  return d.real("grains[0]." + own);
}

}  // namespace

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
    c.k0 = contact_or_own(d, "k_n");
    c.c1 = d.real("contact.gamma_n");
  } else if (model == "hertz") {
    c.law = NormalLaw::kHertz;
    const double e = contact_or_own(d, "young_modulus");
    // Without [contact]'s modulus, the first group's material: its own Poisson ratio where it gives one.
    const double nu = !d.has("contact.young_modulus") && d.has("grains[0].poisson_ratio")
                          ? d.real("grains[0].poisson_ratio")
                          : d.real("contact.poisson_ratio");
    c.e_tilde = e / (1.0 - nu * nu);
    c.zeta = d.real("contact.damping");
    c.hertz_ref_overlap = d.real("contact.hertz_ref_overlap");
    if (m.dim == 2) d.fail("contact.model", "hertz is the 3D sphere law; 2D disks use 'linear' (Peyneau eq. 1.23)");
  } else {
    c.law = NormalLaw::kLinear;
    c.k0 = contact_or_own(d, "k_n");
    c.zeta = d.real("contact.damping");
  }
  c.clip_attractive = d.boolean("contact.clip_attractive");
  c.friction = d.real("contact.friction");
  c.kt_ratio = d.real("contact.kt_over_kn");
  c.zeta_t = d.real("contact.tangential_damping");
}

double hertz_speed_to(const ContactParams& p, double m_eff, double r_eq, double overlap) {
  return std::sqrt(0.8 * hertz_coefficient(p.e_tilde, r_eq) * std::pow(overlap, 2.5) / m_eff);
}

double reference_contact_time(const ContactParams& p, double m_eff, double r_eq) {
  return contact_time(p, m_eff, r_eq, p.law == NormalLaw::kHertz ? p.hertz_ref_overlap * r_eq : 0.0);
}

double contact_time(const ContactParams& p, double m_eff, double r_eq, double max_overlap) {
  if (p.law == NormalLaw::kHertz) {
    // Undamped Hertz collision reaching overlap h_m: 1/2 m* v^2 = (2/5) k_h h_m^(5/2) with
    // F = k_h h^(3/2), k_h = (E~/3) sqrt(2 R_eq); duration kHertzDuration (m*/k_h)^(2/5) v^(-1/5)
    // (Johnson 1985, sec. 11.4; contact_laws.hpp).
    const double kh = hertz_coefficient(p.e_tilde, r_eq);
    return hertz_duration() * std::pow(m_eff / kh, 0.4) * std::pow(hertz_speed_to(p, m_eff, r_eq, max_overlap), -0.2);
  }
  if (p.law == NormalLaw::kSpringDashpot) return p.contact_time_given;
  // Damping-ratio laws: the elastic (undamped) contact time pi / w0. It is the time unit of
  // run.dt_over_tc: the damped duration grows without bound as zeta -> 1 and would allow steps
  // near the stability limit.
  const dem::LinearCoeffs kc = dem::linear_coeffs(p, m_eff);
  return std::numbers::pi / std::sqrt(kc.k / m_eff);
}

std::string damping_key(NormalLaw law) {
  switch (law) {
    case NormalLaw::kHooke: return "contact.gamma_n";
    case NormalLaw::kSpringDashpot: return "contact.restitution";
    case NormalLaw::kHertz:
    case NormalLaw::kLinear: break;
  }
  return "contact.damping";
}

namespace {

// a b / (a + b); where that overflows or underflows (masses of 1e300 or 1e-200), as
// lo / (1 + lo / hi); the same bits elsewhere.
double reduced_mass(double a, double b) {
  const double r = a * b / (a + b);
  if (r > 0 && r < HUGE_VAL) return r;
  const double lo = std::min(a, b), hi = std::max(a, b);
  return lo / (1.0 + lo / hi);
}

// The keys that set a contact law's stiffness and its damping: a group's or a wall's own modulus
// or spring (the tables under `prefixes`, in order) where it gives one, else [contact]'s.
struct LawKeys {
  std::string stiffness, damping;
};
LawKeys law_keys(const SceneDesc& d, NormalLaw law, std::initializer_list<std::string> prefixes = {}) {
  LawKeys keys;
  switch (law) {
    case NormalLaw::kHertz: keys = {"contact.young_modulus", damping_key(law)}; break;
    case NormalLaw::kHooke: keys = {"contact.k_n", damping_key(law)}; break;
    case NormalLaw::kLinear: keys = {"contact.k_n", damping_key(law)}; break;
    case NormalLaw::kSpringDashpot: return {"contact.contact_time", damping_key(law)};
  }
  const std::string own = law == NormalLaw::kHertz ? "young_modulus" : "k_n";
  for (const std::string& prefix : prefixes)
    if (d.has(prefix + own)) return {prefix + own, keys.damping};
  return keys;
}

}  // namespace

std::string stiffness_key(const SceneDesc& d, NormalLaw law, std::initializer_list<std::string> prefixes) {
  const std::string base = law_keys(d, law).stiffness;  // [contact]'s (a contact time: no material's own)
  if (law == NormalLaw::kSpringDashpot) return base;
  const std::string own = law == NormalLaw::kHertz ? "young_modulus" : "k_n";
  std::string key = base;
  double softest = HUGE_VAL;
  for (const std::string& prefix : prefixes) {
    if (!d.has(prefix + own) && !d.has(base)) continue;  // a rigid wall, in a scene whose materials are all their own
    const std::string k = d.has(prefix + own) ? prefix + own : base;
    if (const double v = d.real(k); v < softest) {
      softest = v;
      key = k;
    }
  }
  return key;
}

namespace {

// A law's normal mode for reduced mass m_eff and reduced radius r_eq: its stiffness (Hertz's at
// the largest allowed overlap, limits.max_overlap r_min, where it is stiffest) and damping ratio.
struct NormalMode {
  double k, zeta;
};
NormalMode normal_mode(const ContactParams& p, const Model& m, double m_eff, double r_eq) {
  if (p.law == NormalLaw::kHertz)
    return {0.5 * p.e_tilde * std::sqrt(2.0 * r_eq * m.limits.max_overlap * m.r_min), p.zeta};
  const LinearCoeffs kc = linear_coeffs(p, m_eff);
  return {kc.k, kc.c / (2.0 * std::sqrt(kc.k * m_eff))};
}

// The numbers a contact's scales are made of, each with the key that set it. Numbers at the ends of
// the doubles' range (a tiny radius, a huge modulus) can make a scale 0, infinite or NaN: a scene
// that cannot be integrated, refused at the key of the number that took it out of the range.
struct ScaleInputs {
  double m_eff, k, zeta;
  std::string mass_key;
  LawKeys law;
};

// `known`: how many of m*, k and zeta (in that order) the scale is made of, shown with it.
void refuse_unless_finite(const SceneDesc& d, const std::string& key, const std::string& name, double value,
                          bool zero_allowed, const ScaleInputs& in, int known) {
  if (std::isfinite(value) && (value > 0 || (zero_allowed && value == 0))) return;
  std::string made_of;
  if (known >= 1) made_of += "lightest pair m* = " + format_number(in.m_eff);
  if (known >= 2) made_of += ", stiffness " + format_number(in.k);
  if (known >= 3) made_of += ", damping ratio " + format_number(in.zeta);
  d.fail(key, "the contacts' " + name + " is " + format_number(value) + (made_of.empty() ? "" : " (" + made_of + ")") +
                  ": it must be finite and " + (zero_allowed ? "not negative" : "positive") +
                  ", and the value here takes it out of the range of floating-point numbers");
}

// The reduced mass, the stiffness and the damping ratio in turn, each at its own key; then the time
// scales made of them (sqrt(m*/k), and the damping for the stability limit), at the key of the
// factor farthest from 1 in magnitude: the one that took the scale out of the range.
void check_scales(const SceneDesc& d, const ScaleInputs& in,
                  std::initializer_list<std::pair<const char*, double>> times) {
  refuse_unless_finite(d, in.mass_key, "reduced mass", in.m_eff, false, in, 0);
  refuse_unless_finite(d, in.law.stiffness, "stiffness", in.k, false, in, 1);
  const double mass_far = std::abs(std::log(in.m_eff)), k_far = std::abs(std::log(in.k));
  // (an infinite ratio from a dashpot of 1e308 is the dashpot's; from m* k underflowing, as a density
  // of 1e-300 makes it, the mass's or the spring's)
  const bool extreme = std::max(mass_far, k_far) > 600;
  refuse_unless_finite(d,
                       !extreme           ? in.law.damping
                       : mass_far > k_far ? in.mass_key
                                          : in.law.stiffness,
                       "damping ratio", in.zeta, true, in, 2);
  const double zeta_far = !(in.zeta > 1) ? 0.0 : std::isfinite(in.zeta) ? std::log(in.zeta) : extreme ? 0.0 : HUGE_VAL;
  const std::string& key = zeta_far > std::max(mass_far, k_far) ? in.law.damping
                           : mass_far > k_far                   ? in.mass_key
                                                                : in.law.stiffness;
  for (const auto& [name, value] : times) refuse_unless_finite(d, key, name, value, false, in, 3);
}

}  // namespace

void derive_contact_scales(const SceneDesc& d, Model& m) {
  // Lightest pair: the two lightest free grains, or one free grain against a wall or a frozen
  // grain (m* = m) when it is alone.
  std::vector<std::pair<double, int64_t>> free_mass;  // mass, grain
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i]) free_mass.emplace_back(m.init.mass[i], i);
  if (free_mass.empty()) free_mass.emplace_back(m.init.mass[0], 0);
  std::partial_sort(free_mass.begin(), free_mass.begin() + std::min<size_t>(2, free_mass.size()), free_mass.end());
  const double m0 = free_mass[0].first;
  m.m_eff_min = free_mass.size() >= 2 ? reduced_mass(m0, free_mass[1].first) : m0;
  const int64_t lightest = free_mass[0].second;
  const std::string mass_key = grain_mass_key(d, m.init.group[lightest], m.dim, m.init.radius[lightest]);
  const ContactParams& c = m.contact;
  const double r_eq = m.r_min;  // reduced radius of two of the smallest grains
  // t_c quoted at Hertz's reference overlap; stability checked at the largest allowed overlap.
  m.t_contact = reference_contact_time(c, m.m_eff_min, r_eq);
  m.tc_pair = {c, m.m_eff_min, r_eq, -1, -1};
  const NormalMode scene_mode = normal_mode(c, m, m.m_eff_min, r_eq);
  m.k_max = scene_mode.k;
  const double zeta = m.zeta_max = scene_mode.zeta;
  const bool hertz = c.law == NormalLaw::kHertz;
  m.kappa_stiffness_min = m.kappa_stiffness_max = hertz ? c.e_tilde : scene_mode.k;
  m.kappa_softest_key = law_keys(d, c.law).stiffness;
  double normal_limit = verlet_stability_limit(std::sqrt(m.k_max / m.m_eff_min), zeta);
  check_scales(d, {m.m_eff_min, m.k_max, zeta, mass_key, law_keys(d, c.law)},
               {{"contact time", m.t_contact}, {"stability limit of the time step", normal_limit}});
  // (where the groups have laws of their own, the scene's is no pair's: theirs set the limit below)
  m.dt_stable = m.pair_contact.empty() ? normal_limit : std::numeric_limits<double>::infinity();
  m.dt_stable_tangential = false;
  m.k_stable = m.k_max;
  m.m_eff_stable = m.m_eff_min;
  // The tangential spring of a contact that can hold one: its mode moves the grains and turns them,
  // stiffness k_t (1 + m r^2 / I) for a reduced mass m* (3 k_t for disks, 3.5 k_t for spheres, any
  // sizes), damping ratio sqrt(1 + m r^2 / I) zeta_t. With k_t / k_n above 1/3 (disks) or 2/7
  // (spheres) it can be the faster mode.
  const double turn = 1.0 + 1.0 / inertia_factor(m.dim);  // 1 + m r^2 / I
  auto tangential = [&](const ContactParams& p, double k, double m_eff, const std::string& m_key, const LawKeys& keys) {
    if (!(p.friction > 0) || !(p.kt_ratio > 0)) return;
    const double kt = turn * p.kt_ratio * k, zt = std::sqrt(turn) * std::max(p.zeta_t, 0.0);
    const double limit = verlet_stability_limit(std::sqrt(kt / m_eff), zt);
    check_scales(d, {m_eff, kt, zt, m_key, keys}, {{"stability limit of the time step", limit}});
    if (limit < m.dt_stable) {
      m.dt_stable = limit;
      m.dt_stable_tangential = true;
      m.k_stable = kt;
      m.m_eff_stable = m_eff;
    }
  };
  // (the scene's law, where it is every pair's, and some pair can form: two free grains, or one
  // and a frozen grain; a law of its own per pair of groups is taken below)
  const bool pairs_form = m.pairs_form();
  if (m.pair_contact.empty() && pairs_form) tangential(c, m.k_max, m.m_eff_min, mass_key, law_keys(d, c.law));
  // Other materials (dem/materials.hpp): the stiffest of their laws with the lightest grains, a
  // grain against a wall (m* = m, R_eq = 2 r) included, may lower the limit.
  auto limit_of = [&](const ContactParams& p, double m_eff, double req, const std::string& m_key,
                      const LawKeys& keys) -> NormalMode {
    const NormalMode mode = normal_mode(p, m, m_eff, req);
    const double k = mode.k, z = mode.zeta;
    const double limit = verlet_stability_limit(std::sqrt(k / m_eff), z);
    check_scales(d, {m_eff, k, z, m_key, keys}, {{"stability limit of the time step", limit}});
    if (limit < normal_limit) {
      normal_limit = limit;
      m.k_max = k;
    }
    if (limit < m.dt_stable) {
      m.dt_stable = limit;
      m.dt_stable_tangential = false;
      m.k_stable = k;
      m.m_eff_stable = m_eff;
    }
    tangential(p, k, m_eff, m_key, keys);
    return mode;
  };
  // Each pair of groups with the lightest pair it can make (two free grains, or a free one and a
  // frozen one), each wall with its group's lightest free grain: a law of its own is not paired
  // with the masses of grains it never touches (a stiff group of heavy grains was checked with
  // the m* of a light group of soft ones, 30 times too strictly).
  const int groups = d.group_count("grains");
  auto group = [](int g) { return "grains[" + std::to_string(g) + "]."; };
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> light(groups, inf), light2(groups, inf), r_small(groups, inf);
  std::vector<char> frozen(groups, 0);
  std::vector<int64_t> light_grain(groups, -1);
  for (int64_t i = 0; i < m.n_grains; ++i) {
    const int g = m.init.group[i];
    r_small[g] = std::min(r_small[g], m.init.radius[i]);
    if (m.init.frozen[i]) {
      frozen[g] = 1;
    } else if (const double mi = m.init.mass[i]; mi < light[g]) {
      light2[g] = light[g];
      light[g] = mi;
      light_grain[g] = i;
    } else {
      light2[g] = std::min(light2[g], mi);
    }
  }
  // Where the groups have laws of their own, t_c (the unit of run.dt_over_tc) is the shortest
  // collision of the pairs of groups that can meet, and kappa's stiffness spans their laws: the
  // scene's [contact] law may be no pair's (every group giving its own k_n, t_c was that of a
  // spring no contact had).
  bool pair_seen = false;
  m.pair_meets.assign(m.pair_contact.size(), 0);
  // t_c from `pair` when its collision is the shortest seen (`first`: the first seen); its duration.
  auto take_shortest = [&](bool first, const Model::ContactTimePair& pair, double zeta_of_pair) {
    const double tc = reference_contact_time(pair.law, pair.m_eff, pair.r_eq);
    if (first || tc < m.t_contact) {
      m.t_contact = tc;
      m.tc_pair = pair;
      m.zeta_max = zeta_of_pair;
    }
    return tc;
  };
  for (size_t q = 0; q < m.pair_contact.size(); ++q) {
    const int gi = static_cast<int>(q) / groups, gj = static_cast<int>(q) % groups;
    double m_eff = inf;
    if (gi == gj && light2[gi] < inf) m_eff = reduced_mass(light[gi], light2[gi]);
    if (gi != gj && light[gi] < inf && light[gj] < inf) m_eff = reduced_mass(light[gi], light[gj]);
    if (frozen[gj] && light[gi] < inf) m_eff = std::min(m_eff, light[gi]);
    if (frozen[gi] && light[gj] < inf) m_eff = std::min(m_eff, light[gj]);
    if (!(m_eff < inf)) continue;  // no such pair can form
    m.pair_meets[q] = 1;
    const ContactParams& p = m.pair_contact[q];
    const double req = 2.0 * reduced_mass(r_small[gi], r_small[gj]);
    const int64_t i = light[gi] <= light[gj] ? light_grain[gi] : light_grain[gj];
    const std::string m_key = grain_mass_key(d, m.init.group[i], m.dim, m.init.radius[i]);
    const LawKeys keys = law_keys(d, c.law, {group(gi), group(gj)});
    const NormalMode mode = limit_of(p, m_eff, req, m_key, keys);
    const double tc = take_shortest(!pair_seen, {p, m_eff, req, gi, gj}, mode.zeta);
    check_scales(d, {m_eff, mode.k, mode.zeta, m_key, keys}, {{"contact time", tc}});
    const double stiffness = hertz ? p.e_tilde : mode.k;
    if (!pair_seen || stiffness < m.kappa_stiffness_min) {
      m.kappa_stiffness_min = stiffness;
      m.kappa_softest_key = stiffness_key(d, c.law, {group(gi), group(gj)});
    }
    m.kappa_stiffness_max = pair_seen ? std::max(m.kappa_stiffness_max, stiffness) : stiffness;
    pair_seen = true;
  }
  // A grain's collisions with the walls, each of the wall's and the group's materials, compete too
  // (two Hertz spheres on a rigid floor had the t_c of their collision with each other, 41 % longer
  // than a bounce on the floor); where no two grains can touch (one free grain, nothing frozen), t_c
  // is the shortest of them (the [contact] law with the grain's mass gave a t_c 16 times shorter
  // than the bounce on a wall softer than [contact]). A wall of the scene's law is no shorter than
  // a pair: its reduced mass and radius are larger.
  bool wall_seen = false;
  for (size_t q = 0; q < m.wall_contact.size(); ++q) {
    const int w = static_cast<int>(q) / groups, g = static_cast<int>(q) % groups;
    if (light_grain[g] < 0) continue;  // a group of frozen grains does not touch a wall
    const int64_t i = light_grain[g];
    const ContactParams& p = m.wall_contact[q];
    const double req = 2.0 * r_small[g];
    const NormalMode mode = limit_of(p, light[g], req, grain_mass_key(d, g, m.dim, m.init.radius[i]),
                                     law_keys(d, c.law, {"walls[" + std::to_string(w) + "].", group(g)}));
    take_shortest(!pairs_form && !wall_seen, {p, light[g], req, g, -1, w}, mode.zeta);
    wall_seen = true;
  }
}

}  // namespace silt::dem
