// compile(SceneDesc) -> Model: geometry, contact law, time step and run length, precomputed once.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/rng.hpp"
#include "core/text.hpp"
#include "scene/contact_setup.hpp"
#include "scene/grain_setup.hpp"
#include "scene/render_settings.hpp"
#include "silt/observables.hpp"

namespace silt {
namespace {

std::string fmt_(double x) { return format_number(x, 6); }


void setup_domain(const SceneDesc& d, Model& m) {
  const auto lo = d.reals("domain.lo"), hi = d.reals("domain.hi");
  if (static_cast<int>(lo.size()) != m.dim) d.fail("domain.lo", "needs " + std::to_string(m.dim) + " entries (scene.dimension)");
  if (static_cast<int>(hi.size()) != m.dim) d.fail("domain.hi", "needs " + std::to_string(m.dim) + " entries (scene.dimension)");
  std::vector<bool> per(m.dim, false);
  if (d.has("domain.periodic")) per = d.booleans("domain.periodic");
  if (static_cast<int>(per.size()) != m.dim) d.fail("domain.periodic", "needs " + std::to_string(m.dim) + " entries");
  for (int k = 0; k < m.dim; ++k) {
    if (!(hi[k] > lo[k])) d.fail("domain.hi", "domain.hi must exceed domain.lo in every direction");
    m.box.lo[k] = lo[k];
    m.box.len[k] = hi[k] - lo[k];
    m.box.periodic[k] = per[k];
  }
}

void setup_gravity(const SceneDesc& d, Model& m) {
  m.gravity = Vec3::Zero();
  if (d.has("gravity.vector")) {
    if (d.has("gravity.magnitude")) d.fail("gravity.magnitude", "give gravity.vector or gravity.magnitude (with gravity.angle), not both");
    const auto g = d.reals("gravity.vector");
    if (static_cast<int>(g.size()) != m.dim) d.fail("gravity.vector", "needs " + std::to_string(m.dim) + " entries");
    for (int k = 0; k < m.dim; ++k) m.gravity[k] = g[k];
    if (d.has("gravity.angle")) d.fail("gravity.angle", "gravity.angle tilts gravity.magnitude; it does not apply to gravity.vector");
  } else if (d.has("gravity.magnitude")) {
    // LAMMPS `fix gravity ... chute angle`: -z tilted toward +x (-y in 2D).
    const double g = d.real("gravity.magnitude");
    const double a = d.real("gravity.angle") * 3.14159265358979323846 / 180.0;
    m.gravity[0] = g * std::sin(a);
    m.gravity[m.dim - 1] = -g * std::cos(a);
  } else if (d.has("gravity.angle")) {
    d.fail("gravity.angle", "gravity.angle needs gravity.magnitude");
  }
}

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
    const double len = wall.normal.norm();
    if (!(len > 0)) d.fail(p + "normal", "the wall normal is zero");
    wall.normal /= len;
    for (int k = 0; k < m.dim; ++k)
      if (m.box.periodic[k] && std::abs(wall.normal[k]) > 1e-12)
        d.fail(p + "normal", "a wall cannot cut a periodic direction (axis " + std::string(1, "xyz"[k]) + ")");
    wall.friction = d.has(p + "friction") ? d.real(p + "friction") : m.contact.friction;
    m.walls.push_back(wall);
  }
}

void setup_box_control(const SceneDesc& d, Model& m) {
  BoxControl& b = m.box_control;
  double grain_mass = 0;
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i]) grain_mass += m.init.mass[i];
  if (d.has("box.pressure") || d.has("shear.stress")) {
    b.mass_factor = d.real("box.mass_factor");
    b.mass = b.mass_factor * grain_mass;
  }
  if (!d.has("box.pressure")) {
    if (d.has("box.controlled")) d.fail("box.controlled", "box.controlled needs box.pressure");
    if (d.has("box.mass_factor") && !d.has("shear.stress")) d.fail("box.mass_factor", "box.mass_factor needs box.pressure or shear.stress");
    return;
  }
  if (m.n_frozen > 0)
    d.fail("box.pressure", "a stress-controlled box cannot hold frozen grains (they would not follow its deformation)");
  b.on = true;
  b.pressure = d.real("box.pressure");
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

// Lees-Edwards simple shear: flow along x, gradient along y, both periodic.
void setup_shear(const SceneDesc& d, Model& m) {
  ShearControl& sh = m.shear;
  const int given = d.has("shear.rate") + d.has("shear.inertial_number") + d.has("shear.stress");
  if (given == 0) return;
  const std::string key = d.has("shear.rate") ? "shear.rate" : (d.has("shear.inertial_number") ? "shear.inertial_number" : "shear.stress");
  if (given > 1) d.fail(key, "give one of shear.rate, shear.inertial_number and shear.stress");
  if (!m.box.periodic[0] || !m.box.periodic[1])
    d.fail(key, "simple shear (Lees-Edwards) needs a domain periodic along x (flow) and y (gradient)");
  if (!m.walls.empty()) d.fail(key, "simple shear by Lees-Edwards conditions has no walls");
  if (m.n_frozen > 0) d.fail(key, "simple shear by Lees-Edwards conditions cannot hold frozen grains");
  sh.on = true;
  m.box.lees_edwards = true;
  if (d.has("shear.rate")) {
    sh.rate = d.real("shear.rate");
  } else if (d.has("shear.inertial_number")) {
    if (!m.box_control.on) d.fail(key, "shear.inertial_number is relative to the imposed pressure: it needs box.pressure");
    // I is linear in gammadot (Peyneau eq. 1.30): the rate of I = 1, scaled.
    sh.rate = d.real("shear.inertial_number") / inertial_number(m, 1.0, m.box_control.pressure);
  } else {
    sh.stress_controlled = true;
    sh.stress = d.real("shear.stress");
  }
}

void setup_time(const SceneDesc& d, Model& m) {
  const bool abs = d.has("run.dt"), rel = d.has("run.dt_over_tc");
  if (abs && rel) d.fail("run.dt_over_tc", "give run.dt or run.dt_over_tc, not both");
  m.dt = abs ? d.real("run.dt") : (rel ? d.real("run.dt_over_tc") : 0.02) * m.t_contact;
  if (m.dt > m.dt_stable) {
    const std::string key = abs ? "run.dt" : "run.dt_over_tc";
    d.fail(key, "time step " + fmt_(m.dt) + " s exceeds the velocity-Verlet stability limit " + fmt_(m.dt_stable) +
                    " s of the stiffest contact (reduced mass " + fmt_(m.m_eff_min) + ", stiffness " + fmt_(m.k_max) +
                    "); reduce " + key + " (run.dt_over_tc <= " + fmt_(m.dt_stable / m.t_contact) + ")");
  }
  if (d.has("run.steps") && d.has("run.time")) d.fail("run.time", "give run.steps or run.time, not both");
  if (d.has("run.steps")) m.run_steps = d.integer("run.steps");
  if (d.has("run.time")) {
    const double n = std::ceil(d.real("run.time") / m.dt - 1e-9);
    if (!(n < 9e18)) d.fail("run.time", "run.time is more than 9e18 time steps of " + fmt_(m.dt) + " s");
    m.run_steps = static_cast<int64_t>(n);
  }
  m.until_static.on = d.boolean("run.stop_when_static");
  m.until_static.force_tol = d.real("run.static_force_tol");
  m.until_static.stress_tol = d.real("run.static_stress_tol");
  m.until_static.ke_tol = d.real("run.static_ke_tol");
  m.prepare.compress = d.boolean("prepare.compress");
  m.prepare.max_steps = d.integer("prepare.max_steps");
  if (m.prepare.compress && !m.box_control.on)
    d.fail("prepare.compress", "the isotropic compression is at the imposed pressure: it needs box.pressure");
  if (m.until_static.on && !m.box_control.on)
    d.fail("run.stop_when_static", "the equilibrium criterion is relative to the imposed pressure: it needs box.pressure");
}

void setup_neighbors(const SceneDesc& d, Model& m) {
  m.skin = d.has("neighbor.skin") ? d.real("neighbor.skin") : 0.1 * m.a_max;
  m.contact_skin = d.has("neighbor.contact_skin") ? d.real("neighbor.contact_skin") : 0.2 * m.skin;
  if (m.contact_skin <= 0) m.contact_skin = m.skin;
  m.sort_grains = d.boolean("neighbor.sort");
  const double range = 2 * m.r_max + m.skin;
  for (int k = 0; k < m.dim; ++k)
    if (m.box.periodic[k] && m.box.len[k] < 2 * range)
      d.fail("domain.hi", "the periodic length along " + std::string(1, "xyz"[k]) + " (" + fmt_(m.box.len[k]) +
                              ") must be at least twice the interaction range 2 r_max + skin = " + fmt_(range));
}

// Energy the scene can supply: initial kinetic energy, the potential energy of free grains
// across the domain, the work of the imposed pressure, and one contact at the largest allowed
// overlap per grain. A run whose kinetic energy exceeds a large multiple of this is unstable.
void setup_limits(const SceneDesc& d, Model& m) {
  m.limits.max_overlap = d.real("limits.max_overlap");
  m.limits.energy_factor = d.real("limits.energy_factor");
  m.limits.check_every = d.integer("limits.check_every");
  double e = 0, vol = 1;
  for (int k = 0; k < m.dim; ++k) vol *= m.box.len[k];
  for (int64_t i = 0; i < m.n_grains; ++i) {
    if (m.init.frozen[i]) continue;
    double v2 = 0, w2 = 0, h = 0;
    for (int k = 0; k < m.dim; ++k) {
      v2 += m.init.v[m.dim * i + k] * m.init.v[m.dim * i + k];
      h += std::abs(m.gravity[k]) * m.box.len[k];
    }
    for (int k = 0; k < m.rot; ++k) w2 += m.init.w[m.rot * i + k] * m.init.w[m.rot * i + k];
    e += 0.5 * m.init.mass[i] * v2 + 0.5 * m.init.inertia[i] * w2 + m.init.mass[i] * h;
  }
  const double dmax = m.limits.max_overlap * m.r_min;
  e += (m.n_grains - m.n_frozen) * 0.5 * m.k_max * dmax * dmax;
  if (m.box_control.on) e += m.box_control.pressure * vol;
  m.limits.energy_scale = e;
}

// Identity of the system a checkpoint belongs to: dimension, periodicity, walls and every
// grain's size, mass, group and frozen flag. Run parameters (friction, time step, pressure, ...)
// are not part of it, so a prepared packing can be restored and run with other values.
uint64_t system_fingerprint(const Model& m) {
  uint64_t h = fnv1a(&m.dim, sizeof m.dim);
  h = fnv1a(&m.n_grains, sizeof m.n_grains, h);
  h = fnv1a(m.box.periodic.data(), sizeof(bool) * 3, h);
  const size_t nw = m.walls.size();
  h = fnv1a(&nw, sizeof nw, h);
  h = fnv1a(m.init.radius.data(), sizeof(double) * m.init.radius.size(), h);
  h = fnv1a(m.init.mass.data(), sizeof(double) * m.init.mass.size(), h);
  h = fnv1a(m.init.frozen.data(), m.init.frozen.size(), h);
  h = fnv1a(m.init.group.data(), sizeof(int32_t) * m.init.group.size(), h);
  return h;
}

}  // namespace

double verlet_stability_limit(double w0, double zeta) {
  return 2.0 / w0 * (std::sqrt(1.0 + zeta * zeta) - zeta);
}

Model compile(const SceneDesc& d) {
  Model m;
  m.desc = d;
  const SceneDesc& D = m.desc;  // read through the copy so that its use marks are the ones checked
  m.scene_file = D.file;
  m.scene_name = D.string("scene.name");
  m.dim = static_cast<int>(D.integer("scene.dimension"));
  m.rot = rot_dim(m.dim);
  setup_domain(D, m);
  setup_gravity(D, m);
  scene::read_contact_law(D, m);
  setup_walls(D, m);
  scene::setup_grains(D, m);
  setup_inertial_mass(m);
  m.scene_hash = system_fingerprint(m);
  setup_box_control(D, m);
  setup_shear(D, m);
  setup_neighbors(D, m);
  m.limits.max_overlap = D.real("limits.max_overlap");
  scene::derive_contact_scales(D, m);
  setup_time(D, m);
  setup_limits(D, m);
  m.observe = D.strings("output.observe");
  for (const std::string& name : m.observe)
    if (auto err = check_observable(name, m); !err.empty()) D.fail("output.observe", err);
  m.sample_every = D.integer("output.every");
  scene::read_render_settings(D, m);
  scene::check_initial_overlaps(m);
  D.check_all_used();
  return m;
}

}  // namespace silt
