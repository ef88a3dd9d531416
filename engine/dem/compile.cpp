// The DEM's part of compile(): contact law, walls, grains, neighbour search, contact time and
// stability limit; then, once every module is in, the energy the scene can supply and the
// initial overlaps.
#include <algorithm>
#include <cmath>

#include "dem/contact_laws.hpp"
#include "dem/contact_setup.hpp"
#include "dem/grain_setup.hpp"
#include "dem/materials.hpp"
#include "dem/module.hpp"
#include "silt/text.hpp"

namespace silt::dem {
namespace {

void setup_walls(const SceneDesc& d, Model& m) {
  const int n = d.group_count("walls");
  for (int w = 0; w < n; ++w) {
    const std::string p = "walls[" + std::to_string(w) + "].";
    const auto pt = d.reals(p + "point"), nr = d.reals(p + "normal");
    if (static_cast<int>(pt.size()) != m.dim) d.fail(p + "point", "needs " + std::to_string(m.dim) + " entries");
    if (static_cast<int>(nr.size()) != m.dim) d.fail(p + "normal", "needs " + std::to_string(m.dim) + " entries");
    Wall wall;
    wall.point = Vec3::Zero();
    wall.normal = Vec3::Zero();
    for (int k = 0; k < m.dim; ++k) {
      wall.point[k] = pt[k];
      wall.normal[k] = nr[k];
    }
    // A normal whose squares leave a double's range ([0, 1e200] read as a wall of infinite normal,
    // [0, 1e-300] as a zero one) by hypot, which does not square; others as before (their bits).
    double len = wall.normal.norm();
    if (!(std::isfinite(len) && len > 1e-150)) len = std::hypot(wall.normal[0], wall.normal[1], wall.normal[2]);
    if (!(len > 0)) d.fail(p + "normal", "the wall normal is zero");
    wall.normal /= len;
    for (int k = 0; k < m.dim; ++k)
      if (m.box.periodic[k] && std::abs(wall.normal[k]) > 1e-12)
        d.fail(p + "normal", "a wall cannot cut a periodic direction (axis " + std::string(1, "xyz"[k]) + ")");
    // The grains' side, where the normal points, must hold some of the domain: a normal turned
    // outward left every grain behind the wall ("could not place grain 1 at random", or a grain
    // overlapping the wall at t = 0).
    // (the farthest a corner of the domain is in front of the wall)
    if (!(m.box.span_along(wall.normal.data(), m.dim)[1] > wall.normal.dot(wall.point)))
      d.fail(p + "normal",
             "the normal points out of the domain: all of the domain is behind the wall, and grains "
             "live on the side the normal points to; turn the normal around");
    wall.friction = d.has(p + "friction") ? d.real(p + "friction") : m.contact.friction;
    m.walls.push_back(wall);
  }
}

// The mass unit of the inertial number I = gammadot sqrt(m / (a^(d-2) P)): Peyneau (2009) takes
// "the mass of a grain of diameter a", a the largest diameter (sec. 5.3.3, for the 2D disks of
// diameters in [0.7 a, a]; the monodisperse spheres of ch. 3 have a single mass). With several
// densities, that of the free grains' total mass over their total volume.
void setup_inertial_mass(Model& m) {
  double mass = 0, volume = 0;
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i] || m.n_frozen == m.n_grains) {
      mass += m.init.mass[i];
      volume += grain_volume(m.dim, m.init.radius[i]);
    }
  m.m_a = mass / volume * grain_volume(m.dim, 0.5 * m.a_max);
}

void setup_neighbors(const SceneDesc& d, Model& m) {
  m.skin = d.has("neighbor.skin") ? d.real("neighbor.skin") : 0.1 * m.a_max;
  m.contact_skin = d.has("neighbor.contact_skin") ? d.real("neighbor.contact_skin") : 0.2 * m.skin;
  if (m.contact_skin <= 0) m.contact_skin = m.skin;
  m.sort_grains = d.boolean("neighbor.sort");
  const double range = m.interaction_range();
  for (int k = 0; k < m.dim; ++k)
    if (m.box.periodic[k] && m.box.len[k] < 2 * range)
      d.fail("domain.hi",
             "the periodic length along " + std::string(1, "xyz"[k]) + " (" + format_number(m.box.len[k]) +
                 ") must be at least twice the interaction range 2 r_max + skin = " + format_number(range));
}

// Energy the scene can supply: initial kinetic energy, the potential energy of free grains
// across the domain, the work of the imposed pressure, and one contact at the largest allowed
// overlap per grain. A run whose kinetic energy exceeds a large multiple of this is unstable.
// Gravity along a periodic axis has no bottom: the free grains' momentum p along it grows at most
// as p0 + M g t, and g's work by time t is at most g (p0 t + M g t^2 / 2).
void setup_energy_scale(Model& m) {
  double e = 0, vol = 1, g_periodic2 = 0, mass = 0, momentum = 0;
  for (int k = 0; k < m.dim; ++k) {
    vol *= m.box.len[k];
    if (m.box.periodic[k]) g_periodic2 += m.gravity[k] * m.gravity[k];
  }
  for (int64_t i = 0; i < m.n_grains; ++i) {
    if (m.init.frozen[i]) continue;
    double v2 = 0, w2 = 0, h = 0;
    for (int k = 0; k < m.dim; ++k) {
      v2 += m.init.v[m.dim * i + k] * m.init.v[m.dim * i + k];
      h += std::abs(m.gravity[k]) * m.box.len[k];
    }
    for (int k = 0; k < m.rot; ++k) w2 += m.init.w[m.rot * i + k] * m.init.w[m.rot * i + k];
    e += 0.5 * m.init.mass[i] * v2 + 0.5 * m.init.inertia[i] * w2 + m.init.mass[i] * h;
    mass += m.init.mass[i];
    momentum += m.init.mass[i] * std::sqrt(v2);
  }
  const double dmax = m.limits.max_overlap * m.r_min;
  e += (m.n_grains - m.n_frozen) * 0.5 * m.k_max * dmax * dmax;
  if (m.box_control.on) e += m.box_control.pressure * vol;
  m.limits.energy_scale = e;
  m.limits.energy_per_s = std::sqrt(g_periodic2) * momentum;
  m.limits.energy_per_s2 = 0.5 * mass * g_periodic2;
}

// A friction with no tangential spring: the tangential dashpot is a fraction of the spring's
// critical damping, so there is no tangential force at all (kt_over_kn = 0 with mu = 0.5 and a
// tangential damping of 1 slid an oblique impact on as if frictionless, without a word).
void refuse_friction_without_spring(const SceneDesc& d, const Model& m) {
  if (m.contact.kt_ratio > 0) return;
  bool walls = false;
  for (const ContactParams& w : m.wall_contact) walls = walls || w.friction > 0;
  if (!m.pair_friction() && !walls) return;
  d.fail("contact.kt_over_kn",
         "contact.kt_over_kn = 0 leaves no tangential force (the tangential dashpot is a fraction of the spring's "
         "critical damping), so the friction given would do nothing: give kt_over_kn > 0, or friction 0");
}

}  // namespace

void compile_dem(const SceneDesc& d, Model& m) {
  check_explicit_positions(d, m.dim);
  read_contact_law(d, m);
  setup_walls(d, m);
  setup_grains(d, m);
  setup_materials(d, m);
  refuse_friction_without_spring(d, m);
  setup_inertial_mass(m);
  m.scene_hash = system_fingerprint(m, m.init.frozen);
  setup_neighbors(d, m);
  derive_contact_scales(d, m);
  m.propose_dt(0.02 * m.t_contact);
}

void refresh_frozen(Model& m) {
  m.n_frozen = std::count(m.init.frozen.begin(), m.init.frozen.end(), 1);
  setup_inertial_mass(m);
  m.scene_hash = system_fingerprint(m, m.init.frozen);
  setup_energy_scale(m);
}

// The time step against the velocity-Verlet stability limit of the fastest contact mode, at the key
// that set it (and, for a tangential spring's mode, the ratio that made it the faster).
void check_time_step(const SceneDesc& d, const Model& m) {
  if (!(m.dt > m.dt_stable)) return;
  const bool given = d.has("run.dt") || d.has("run.dt_over_tc");
  const std::string key = d.has("run.dt") ? "run.dt" : "run.dt_over_tc";
  // The default step (0.02 t_c) exceeds the limit only where a dashpot or k_t / k_n has shortened
  // it: the refusal is located there (it was at the [run] table that gives no step).
  const std::string at = given                     ? key
                         : !m.dt_stable_tangential ? damping_key(m.contact.law)
                         : m.contact.zeta_t > 1    ? "contact.tangential_damping"
                                                   : "contact.kt_over_kn";
  const std::string mode = m.dt_stable_tangential
                               ? " of the stiffest contact's tangential spring (reduced mass " +
                                     format_number(m.m_eff_stable) +
                                     ", stiffness k_t (1 + m r^2 / I) = " + format_number(m.k_stable) + ")"
                               : " of the stiffest contact (reduced mass " + format_number(m.m_eff_stable) +
                                     ", stiffness " + format_number(m.k_stable) + ")";
  d.fail(at, "time step " + format_number(m.dt) + m.unit("s") + (given ? "" : " (the default)") +
                 " exceeds the velocity-Verlet stability limit " + format_number(m.dt_stable) + m.unit("s") + mode +
                 "; " +
                 (key == "run.dt" ? "reduce run.dt to below " + format_number(m.dt_stable) + m.unit("s")
                                  : (given ? "reduce " : "give ") + std::string("run.dt_over_tc below ") +
                                        format_number(m.dt_stable / m.t_contact)) +
                 (m.dt_stable_tangential ? std::string(" or reduce contact.kt_over_kn") +
                                               (m.contact.zeta_t > 0 ? " or contact.tangential_damping" : "")
                                         : std::string()));
}

// A weight that alone presses a grain into what it rests on beyond limits.max_overlap (linear
// contacts: m g / (k_n r); Hertz, whose force at that overlap is less than k_max times it, sooner):
// every grain that comes to rest fails the run. gravity.magnitude = 1e300 printed a weight overlap
// of inf, `ok`, and the run failed at its first step.
void check_weight(const SceneDesc& d, const Model& m) {
  const double g = m.gravity.norm();
  // (with nothing to rest on, no wall nor frozen grain, a grain falls freely whatever its weight)
  if (!(g > 0) || m.k_max <= 0 || m.n_grains == m.n_frozen || (m.walls.empty() && m.n_frozen == 0)) return;
  const double overlap = m.m_mean * g / (m.k_max * m.r_mean);
  if (overlap > m.limits.max_overlap)
    d.fail(d.first_given({"gravity.magnitude", "gravity.vector"}, "gravity.magnitude"),
           "a grain's weight alone (m g = " + format_number(m.m_mean * g, 4) + m.unit("N") +
               ") presses it into what it rests on by " + format_number(overlap, 3) +
               " of its radius (m g / (k_n r)), beyond limits.max_overlap = " + format_number(m.limits.max_overlap, 3) +
               ", where the run fails: reduce the gravity below " +
               format_number(m.limits.max_overlap * m.k_max * m.r_mean / m.m_mean, 4) + m.unit("m/s^2") +
               " or stiffen the contacts");
  // A wall of its own, softer material under the weight (its normal against gravity): the grain
  // resting on it, each free grain with its group's law (the heaviest for its size presses most),
  // Hertz by its static overlap (F = (E~/3) sqrt(2 R) h^(3/2), R = 2 r against a wall). A wall's
  // young_modulus = 1e-300 passed, and the run failed when the first grain landed, advising a
  // larger contact.young_modulus.
  const int groups = static_cast<int>(m.materials.size());
  for (size_t w = 0; w < m.walls.size(); ++w) {
    const double press = -m.walls[w].normal.dot(m.gravity);  // the weight's part along the normal, per mass
    if (!(press > 0)) continue;
    double worst = 0;
    int64_t worst_grain = -1;
    for (int64_t i = 0; i < m.n_grains; ++i) {
      if (m.init.frozen[i]) continue;
      const double r = m.init.radius[i];
      const double h =
          static_overlap(m.wall_contact[w * groups + m.init.group[i]], m.init.mass[i], 2.0 * r, m.init.mass[i] * press);
      if (h / r > worst) {
        worst = h / r;
        worst_grain = i;
      }
    }
    if (!(worst > m.limits.max_overlap) || worst_grain < 0) continue;
    const int grp = m.init.group[worst_grain];
    const std::string key =
        stiffness_key(d, m.wall_contact[w * groups + grp].law,
                      {"walls[" + std::to_string(w) + "].", "grains[" + std::to_string(grp) + "]."});
    d.fail(key, "the weight of grain " + std::to_string(worst_grain) + " (of grains[" + std::to_string(grp) +
                    "]) alone presses it into walls[" + std::to_string(w) + "] by " + format_number(worst, 3) +
                    " of its radius under the law of that wall with its group, beyond limits.max_overlap = " +
                    format_number(m.limits.max_overlap, 3) + ", where the run fails: stiffen that contact (" + key +
                    ")");
  }
}

// Initial velocities no scene can have: a grain that crosses the whole domain in one time step
// (a speed of 1e308, say) is not simulated, it is thrown away, and every neighbour build after
// it would span the distance.
void check_initial_speeds(const SceneDesc& d, const Model& m) {
  double extent = 0;
  for (int k = 0; k < m.dim; ++k) extent = std::max(extent, m.box.len[k]);
  for (int64_t i = 0; i < m.n_grains; ++i) {
    if (m.init.frozen[i]) continue;
    // Without squaring, which overflows above 1e154 m/s: the speed given is the speed shown.
    const double* vi = &m.init.v[m.dim * i];
    const double v = std::hypot(vi[0], vi[1], m.dim == 3 ? vi[2] : 0.0);
    if (!(v * m.dt <= extent)) {
      const std::string p = "grains[" + std::to_string(m.init.group[i]) + "].";
      d.fail(d.has(p + "velocities") ? p + "velocities" : (d.has(p + "temperature") ? p + "temperature" : "run.dt"),
             "grain " + std::to_string(i) + " starts at " + format_number(v) + m.unit("m/s") +
                 ": it would cross the whole domain (" + format_number(extent) + m.unit("m") +
                 ") in one time step of " + format_number(m.dt) + m.unit("s") + ": reduce its speed or run.dt");
    }
    // A spin alike: the surface speed w r ([[1e300]] was reported at the file's first line, as an
    // energy the scene cannot supply).
    const double* wi = &m.init.w[m.rot * i];
    const double w = m.rot == 3 ? std::hypot(wi[0], wi[1], wi[2]) : std::abs(wi[0]);
    if (!(w * m.init.radius[i] * m.dt <= extent)) {
      const std::string p = "grains[" + std::to_string(m.init.group[i]) + "].";
      d.fail(d.has(p + "angular_velocities") ? p + "angular_velocities" : "run.dt",
             "grain " + std::to_string(i) + " starts spinning at " + format_number(w) + m.unit("rad/s") +
                 ": its surface would travel farther than the whole domain (" + format_number(extent) + m.unit("m") +
                 ") in one time step of " + format_number(m.dt) + m.unit("s") + ": reduce its spin or run.dt");
    }
  }
}

void finish_dem(const SceneDesc& d, Model& m) {
  check_time_step(d, m);
  check_weight(d, m);
  check_initial_speeds(d, m);
  setup_energy_scale(m);
  if (!std::isfinite(m.limits.energy_scale))
    d.fail("limits.energy_factor", "the energy the scene can supply is not finite (its grains, heights or pressure)");
  // With the radii and the skin known: their pairs too.
  const int last = d.group_count("grains") - 1;
  const std::string p = "grains[" + std::to_string(last) + "].";
  check_memory(d, m, m.n_grains, d.has(p + "count") ? p + "count" : p + "placement");
  check_initial_overlaps(m);
}

}  // namespace silt::dem
