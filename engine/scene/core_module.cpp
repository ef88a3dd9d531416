// The core module: what every scene has. Its keys (scene, domain, gravity, run, output, limits),
// their constraints, the observables of time and box, its part of compile() (dimension, domain,
// gravity, limits) and of `silt check`, and its steerable values (gravity, time step).
#include <cmath>
#include <numbers>
#include <sstream>

#include <algorithm>

#include "scene/core_module.hpp"
#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt::scene {
namespace {

std::vector<KeySpec> core_keys() {
  using K = KeyType;
  using S = std::vector<std::string>;
  // clang-format off
  std::vector<KeySpec> s = {
      // ---- scene
      {"scene.name", K::kString, Value(std::string()), Range::any(), "", false, {}, "A name for the scene, shown in outputs."},
      {"scene.dimension", K::kInt, Value(int64_t{3}), Range::closed(2, 3), "", false, {}, "2: disks in the x-y plane; 3: spheres."},
      {"scene.units", K::kString, Value(std::string("SI")), Range::any(), "", false, {"SI", "reduced"}, "SI: every value in SI units (m, kg, s), as labelled. reduced: the scene is in reduced units (the grain diameter, mass and sqrt(d/g) as units, LAMMPS's lj style); numbers are unchanged, and frames, print, stats and params label no SI units."},
      {"scene.seed", K::kInt, Value(int64_t{1}), Range::closed(0, 4.6e18), "", false, {}, "Seed of every random draw (radii, placement, velocities)."},
      // ---- domain
      {"domain.lo", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "Lower corner of the domain (one entry per dimension)."},
      {"domain.hi", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "Upper corner of the domain."},
      {"domain.periodic", K::kBoolList, std::nullopt, Range::any(), "", false, {}, "Periodic flag per direction (default: none)."},
      // ---- gravity
      {"gravity.vector", K::kRealList, std::nullopt, Range::any(), "m/s^2", true, {}, "Gravity vector; or give gravity.magnitude and gravity.angle."},
      {"gravity.magnitude", K::kReal, std::nullopt, Range::non_negative(), "m/s^2", true, {}, "|g|, pointing along -z (3D) or -y (2D) before the tilt."},
      {"gravity.angle", K::kReal, Value(0.0), Range::closed(-90, 90), "deg", true, {}, "Chute angle: gravity tilted from -z (-y in 2D) toward +x."},
      // ---- run
      {"run.dt", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "Time step."},
      {"run.dt_over_tc", K::kReal, std::nullopt, Range::open_closed(0, 1), "", true, {}, "Time step as a fraction of the contact time (default 0.02)."},
      {"run.steps", K::kInt, std::nullopt, Range::closed(0, static_cast<double>(kMaxRunSteps)), "", false, {}, "Run length in steps."},
      {"run.time", K::kReal, std::nullopt, Range::non_negative(), "s", false, {}, "Run length in simulated time."},
      {"run.stop_when_static", K::kBool, Value(false), Range::any(), "", false, {}, "Stop when the packing is in equilibrium (forces, stresses and kinetic energy below the tolerances)."},
      {"run.static_force_tol", K::kReal, Value(1e-4), Range::positive(), "", false, {}, "Equilibrium: largest net force on a grain / (a^(d-1) P)."},
      {"run.static_stress_tol", K::kReal, Value(1e-4), Range::positive(), "", false, {}, "Equilibrium: |sigma_aa / P - 1| on controlled axes."},
      {"run.static_ke_tol", K::kReal, Value(1e-8), Range::positive(), "", false, {}, "Equilibrium: translational kinetic energy per grain / (a^d P)."},
      // ---- output
      {"output.observe", K::kStringList, Value(std::vector<std::string>{"t", "step", "ke"}), Range::any(), "", false, {}, "Observables written to the stats file (a fluid without grains: t, step, fluid.ke)."},
      {"output.every", K::kInt, Value(int64_t{100}), Range::closed(1, 1e12), "", false, {}, "Sample every N steps."},
      {"output.profile_axis", K::kString, std::nullopt, Range::any(), "", false, S{"x", "y", "z"}, "Axis across which the summary's velocity profile is taken, in slabs (default: y under shear, else none); the chute's is z."},
      {"output.profile_component", K::kString, Value(std::string("x")), Range::any(), "", false, S{"x", "y", "z"}, "Velocity component of the profile (with the shear flow)."},
      {"output.profile_slabs", K::kInt, std::nullopt, Range::closed(1, 10000), "", false, {}, "Slabs of the profile (default: about one largest diameter thick, 4 to 40)."},
      // ---- limits
      {"limits.max_overlap", K::kReal, Value(0.2), Range::open_closed(0, 1), "", false, {}, "Stop when an overlap exceeds this fraction of the smaller radius."},
      {"limits.energy_factor", K::kReal, Value(100.0), Range::open_closed(1, 1e12), "", false, {}, "Stop when kinetic energy exceeds this factor times the energy the scene can supply."},
      {"limits.check_every", K::kInt, Value(int64_t{100}), Range::closed(1, 1e9), "", false, {}, "Steps between energy checks (and saved restart points)."},

  };
  // clang-format on
  for (KeySpec& k : s) {
    if (k.path == "run.dt") k.computed = [](const Model& m) { return format_number(m.dt); };
    if (k.path == "run.dt_over_tc")
      k.computed = [](const Model& m) { return m.t_contact > 0 ? format_number(m.dt / m.t_contact) : std::string(); };
    if (k.path == "gravity.vector")
      k.computed = [](const Model& m) {
        std::string v = "[";
        for (int c = 0; c < m.dim; ++c) v += (c ? ", " : "") + format_number(m.gravity[c]);
        return v + "]";
      };
    if (k.path == "run.steps") k.computed = [](const Model& m) { return std::to_string(m.run_steps); };
    if (k.path == "output.profile_slabs")
      k.computed = [](const Model& m) {
        return m.profile.axis >= 0 && m.profile.slabs == 0
                   ? std::string("box length at the start / largest diameter, 4 to 40")
                   : std::string();
      };
    if (k.path == "output.profile_axis")
      k.computed = [](const Model& m) {
        return m.profile.axis >= 0 ? std::string(1, "xyz"[m.profile.axis]) : std::string();
      };
  }
  return s;
}

std::vector<KeyRule> core_rules() {
  return {
      KeyRule::one_of({{"run.dt"}, {"run.dt_over_tc"}}),
      KeyRule::one_of({{"run.steps"}, {"run.time"}}),
      KeyRule::one_of({{"gravity.vector"}, {"gravity.magnitude", "gravity.angle"}}),
      KeyRule::requires_any("gravity.angle", {"gravity.magnitude"}, "it tilts gravity.magnitude"),
      KeyRule::requires_any("run.stop_when_static", {"box.pressure"},
                            "the equilibrium criterion is relative to the imposed pressure"),
  };
}

const char* kAxes = "xyz";

std::vector<ObservableSpec> core_observables() {
  return {
      {"t", "s", "simulated time", [](const ObservableContext& c, const ObservableArgs&) { return c.s.t; }},
      {"step", "", "step index",
       [](const ObservableContext& c, const ObservableArgs&) { return static_cast<double>(c.s.step); }},
      {"dt", "s", "time step of the last step",
       [](const ObservableContext& c, const ObservableArgs&) { return c.s.dt; }},
      {"box.L{a}", "m", "box length",
       [](const ObservableContext& c, const ObservableArgs& a) { return c.s.box.len[a.a]; }},
  };
}

void setup_domain(const SceneDesc& d, Model& m) {
  const auto lo = d.reals("domain.lo"), hi = d.reals("domain.hi");
  if (static_cast<int>(lo.size()) != m.dim)
    d.fail("domain.lo", "needs " + std::to_string(m.dim) + " entries (scene.dimension)");
  if (static_cast<int>(hi.size()) != m.dim)
    d.fail("domain.hi", "needs " + std::to_string(m.dim) + " entries (scene.dimension)");
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
    const auto g = d.reals("gravity.vector");
    if (static_cast<int>(g.size()) != m.dim) d.fail("gravity.vector", "needs " + std::to_string(m.dim) + " entries");
    for (int k = 0; k < m.dim; ++k) m.gravity[k] = g[k];
  } else if (d.has("gravity.magnitude")) {
    // LAMMPS `fix gravity ... chute angle`: -z tilted toward +x (-y in 2D).
    const double g = d.real("gravity.magnitude");
    const double a = d.real("gravity.angle") * std::numbers::pi / 180.0;
    m.gravity[0] = g * std::sin(a);
    m.gravity[m.dim - 1] = -g * std::cos(a);
  }
}

void compile_core(const SceneDesc& d, Model& m) {
  m.scene_file = d.file;
  m.scene_name = d.string("scene.name");
  m.reduced_units = d.string("scene.units") == "reduced";
  m.dim = static_cast<int>(d.integer("scene.dimension"));
  m.rot = rot_dim(m.dim);
  setup_domain(d, m);
  setup_gravity(d, m);
  m.limits.max_overlap = d.real("limits.max_overlap");
  m.limits.energy_factor = d.real("limits.energy_factor");
  m.limits.check_every = d.integer("limits.check_every");
}

// The stats columns, once every module is in (their observables).
void finish_core(const SceneDesc& d, Model& m) {
  m.observe = d.strings("output.observe");
  // The default's grain energy means nothing without grains: a fluid's instead.
  if (!d.has("output.observe") && !m.module_on("dem")) m.observe = {"t", "step", "fluid.ke"};
  // (an empty list wrote blank rows with no header; a name twice, its column twice)
  if (m.observe.empty()) d.fail("output.observe", "an empty list samples nothing: give at least one observable");
  for (size_t k = 0; k < m.observe.size(); ++k) {
    const std::string& name = m.observe[k];
    if (auto err = check_observable(name, m); !err.empty()) d.fail("output.observe", err);
    if (std::find(m.observe.begin(), m.observe.begin() + static_cast<long>(k), name) !=
        m.observe.begin() + static_cast<long>(k))
      d.fail("output.observe", "'" + name + "' is listed twice");
  }
  m.sample_every = d.integer("output.every");
  // The summary's velocity profile: across y under shear, else where the scene asks.
  VelocityProfileSpec& p = m.profile;
  p.axis = d.has("output.profile_axis") ? d.string("output.profile_axis")[0] - 'x' : (m.shear.on ? 1 : -1);
  p.component = d.string("output.profile_component")[0] - 'x';
  for (const char* key : {"output.profile_axis", "output.profile_component"})
    if (d.has(key) && d.string(key)[0] - 'x' >= m.dim)
      d.fail(key, std::string(key) + " names an axis this 2D scene does not have");
  // (a scene with no grains gave a profile of zeros)
  if (d.has("output.profile_axis") && m.n_grains == 0)
    d.fail("output.profile_axis", "the velocity profile is the grains', and this scene has none");
  // (profile_component without a profile was taken and did nothing)
  for (const char* key : {"output.profile_slabs", "output.profile_component"})
    if (d.has(key) && p.axis < 0) d.fail(key, std::string(key) + " needs a profile (output.profile_axis)");
  p.slabs = d.has("output.profile_slabs") ? static_cast<int>(d.integer("output.profile_slabs")) : 0;
}

std::string describe_core(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  // (quoted where it holds control characters, which went to the terminal as they were)
  const std::string scene = m.scene_name.empty() ? m.scene_file : m.scene_name;
  const bool plain = std::none_of(scene.begin(), scene.end(), is_control);
  o << "scene        " << (plain ? scene : toml_quoted(scene)) << "\n";
  o << "dimension    " << m.dim << (m.dim == 2 ? " (disks)" : " (spheres)") << "\n";
  o << "modules     ";
  for (const std::string& name : m.modules) o << " " << name;
  o << "\n";
  o << "box          ";
  for (int k = 0; k < m.dim; ++k)
    o << kAxes[k] << " [" << m.box.lo[k] << ", " << m.box.lo[k] + m.box.len[k] << ")"
      << (m.box.periodic[k] ? " periodic" : "") << (k + 1 < m.dim ? ", " : "\n");
  o << "gravity      (";
  for (int k = 0; k < m.dim; ++k) o << m.gravity[k] << (k + 1 < m.dim ? ", " : ")\n");
  return o.str();
}

std::string steer_core(Model& m, const Model& fresh) {
  m.gravity = fresh.gravity;
  m.dt = fresh.dt;
  // (the run length in steps follows the step: `check` and a run's end gave the old step's count)
  m.run_steps = fresh.run_steps;
  m.run_time = fresh.run_time;
  return "";
}

}  // namespace

const ModuleSpec& core_module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "core";
    s.doc = "time, the box, gravity, run length and outputs";
    s.keys = core_keys();
    mark_initial(s.keys, {"scene.seed"});
    s.rules = core_rules();
    s.observables = core_observables();
    s.compile = compile_core;
    s.finish = finish_core;
    s.describe = describe_core;
    s.steer = steer_core;
    return s;
  }();
  return spec;
}

}  // namespace silt::scene
