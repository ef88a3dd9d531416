// Model: everything constant for a run, compiled once from a SceneDesc (MuJoCo's mjModel).
//
// Read-only during a step. Steerable parameters (gravity, friction, time step, imposed
// pressure) are changed between steps by replacing values here; every stage reads them afresh.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "silt/limits.hpp"
#include "silt/module_params.hpp"
#include "silt/scene.hpp"
#include "silt/vec.hpp"

namespace silt {

enum class NormalLaw : uint8_t {
  kSpringDashpot,  // Izard (2014) eq. 3.13-3.17: k_n, gamma_n from restitution and contact time
  kHooke,          // LAMMPS gran/hooke: constant k_n, dashpot m* gamma_n
  kHertz,          // Peyneau (2009) eq. 1.22 / 3.1-3.3: Hertz with dashpot 2 zeta sqrt(m* K_N)
  kLinear,         // Peyneau (2009) eq. 1.23 (2D disks): constant k_n, dashpot 2 zeta sqrt(m* k_n)
};
const char* normal_law_name(NormalLaw law);

// Contact law parameters. For the linear family the pair stiffness and dashpot are
//   k_n(m*) = k0 + k1 m*,   c_n(m*) = c1 m* + 2 zeta sqrt(m* k_n(m*)),
// which covers spring_dashpot (k0 = 0, zeta = 0), hooke (k1 = 0, zeta = 0) and linear (c1 = 0).
struct ContactParams {
  NormalLaw law = NormalLaw::kHooke;
  double k0 = 0, k1 = 0, c1 = 0, zeta = 0;
  double e_tilde = 0;            // Hertz: E / (1 - nu^2) [Pa]
  bool clip_attractive = false;  // Izard eq. 3.13
  double friction = 0;           // Coulomb mu between grains (steerable)
  double kt_ratio = 2.0 / 7.0;   // k_t / k_n
  double zeta_t = 0;             // tangential dashpot, fraction of critical damping
  // As given, for reports.
  double restitution = 0, contact_time_given = 0, hertz_ref_overlap = 0.01;
};

// Three components of a box quantity (lengths, rates, stresses), whatever the dimension.
using Vec3a = std::array<double, 3>;

// What a group of grains, or a wall, is made of (dem/materials.hpp mixes two of them).
struct Material {
  double compliance = 0;  // Hertz: (1 - nu^2) / E [1/Pa]; 0 for a rigid wall
  double k_n = 0;         // hooke, linear: the material's spring [N/m]
  double friction = 0;    // Coulomb coefficient
};

struct Wall {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, pointing into the domain
  double friction = 0;          // grain-wall Coulomb coefficient (steerable)
  // Gap between the wall and a grain of radius r centred at x (D components), negative when they
  // overlap: (x - point) . normal - r.
  template <int D, class V>
  double gap(const V& x, double r) const {
    return (x - point.head<D>()).dot(normal.head<D>()) - r;
  }
  // The same for a grain's coordinates as the state stores them (dim of them).
  double gap(int dim, const double* x, double r) const {
    return dim == 2 ? gap<2>(at<2>(x, 0), r) : gap<3>(at<3>(x, 0), r);
  }
};

// The periodic box. Its lengths may change in time (stress control), so State holds the
// current box; the Model holds the initial one. With Lees-Edwards conditions (simple shear,
// flow along x, gradient along y), the periodic image above the box is shifted along x by
// le_offset: a grain at (x, y) has an image at (x + le_offset, y + L_y).
struct Box {
  std::array<double, 3> lo{0, 0, 0};
  std::array<double, 3> len{1, 1, 1};
  std::array<bool, 3> periodic{false, false, false};
  bool lees_edwards = false;
  double le_offset = 0;  // in [0, len[0])

  // Replace a separation d (dim components) by its nearest image: under Lees-Edwards the y
  // image first, which shifts x by the offset, then x and z.
  void nearest(double* d, int dim) const {
    if (lees_edwards) {
      const double ny = std::nearbyint(d[1] / len[1]);
      d[1] -= ny * len[1];
      d[0] -= ny * le_offset;
    }
    for (int k = 0; k < dim; ++k)
      if (periodic[k]) d[k] -= len[k] * std::nearbyint(d[k] / len[k]);
  }
  // The range [min, max] of n . x over the corners of the box's first dim axes.
  std::array<double, 2> span_along(const double* n, int dim) const {
    std::array<double, 2> span{HUGE_VAL, -HUGE_VAL};
    for (int corner = 0; corner < (1 << dim); ++corner) {
      double at = 0;
      for (int k = 0; k < dim; ++k) at += n[k] * (lo[k] + ((corner >> k) & 1) * len[k]);
      span[0] = std::min(span[0], at);
      span[1] = std::max(span[1], at);
    }
    return span;
  }
};

// Stress-controlled box lengths (Peyneau 2009 eq. 3.11): M d2L/dt2 = (Omega/L)(sigma - P).
// The imposed stress may cycle (Peyneau ch. 5): alternating, Sigma_11 = P (1 + d sin wt) and
// Sigma_22 = P (1 - d sin wt) (eq. 5.3-5.4: the mean pressure constant, the principal directions
// swapping); biaxial, Sigma_11 = P and Sigma_22 = P (1 + d (1 - cos wt)) (eq. 5.15-5.16). Other
// axes stay at P.
enum class StressCycle : uint8_t { kNone, kAlternating, kBiaxial };
// Where the cycles' phase is counted from: phase0 at t0, then w (t - t0), w the cycles' angular
// frequency then. From the start, (0, 0, w): w t. A new w (a steered period or viscous number, a
// scene compiled again over the state, a checkpoint restored under another period) takes over
// at the phase reached, so the imposed stresses never jump and the cycles never run back. The
// origin is part of the state (shear/cycle_origin.hpp), which checkpoints carry.
struct CycleOrigin {
  double t0 = 0, phase0 = 0, omega = 0;
  double phase(double t) const { return phase0 + omega * (t - t0); }
};
struct BoxControl {
  bool on = false;
  std::array<bool, 3> controlled{false, false, false};
  double pressure = 0;     // imposed sigma_aa [Pa], compression positive (steerable)
  double mass_factor = 1;  // M = mass_factor * total free grain mass (steerable)
  double mass = 0;         // M [kg]
  StressCycle cycle = StressCycle::kNone;
  double cycle_amplitude = 0;  // d = delta P / P
  double cycle_omega = 0;      // w [1/s]
  // The imposed sigma_aa at time t, the cycles' phase counted from `origin` (CycleOrigin).
  double stress(int axis, const CycleOrigin& origin, double t) const {
    const double w = origin.phase(t);
    switch (cycle) {
      case StressCycle::kAlternating:
        return axis == 0 ? pressure * (1 + cycle_amplitude * std::sin(w))
                         : (axis == 1 ? pressure * (1 - cycle_amplitude * std::sin(w)) : pressure);
      case StressCycle::kBiaxial: return axis == 1 ? pressure * (1 + cycle_amplitude * (1 - std::cos(w))) : pressure;
      default: return pressure;
    }
  }
};

// Simple shear by Lees-Edwards conditions: flow along x, gradient along y (Peyneau 2009 sec. 3.1.4).
// Either the shear rate is imposed (liquid regime), or the shear stress (solid regime, eq. 3.12:
// M L_x L_y / Omega d(gammadot)/dt = tau - tau_imposed... with tau = -sigma_xy).
struct ShearControl {
  bool on = false;
  double rate = 0;  // imposed gammadot [1/s] (steerable); initial value under stress control
  bool stress_controlled = false;
  double stress = 0;  // imposed shear stress tau [Pa] (steerable)
};

// Preparation before the run: Peyneau's "procedure O" (2009 sec. 3.1.2), an isotropic
// compression of the initial grains at the imposed pressure, every periodic length controlled
// and no shear, until static (run.static_* tolerances) or max_steps.
struct Preparation {
  bool compress = false;
  int64_t max_steps = 0;
  double dilation = 1;  // then the centres and the box lengths times this (Peyneau 2009 sec. 2.3.1)
  double pressure = 0;  // of the compression when the run has no box pressure (0: box_control's)
  double phi = 0;       // stop at this solid fraction (0: at equilibrium)
};

// Initial grains, as placed by compile(); State is made from them.
struct GrainInit {
  std::vector<double> x, v, w;  // N*D, N*D, N*kRotDim
  std::vector<double> radius, mass, inertia;
  std::vector<uint8_t> frozen;
  // Of those, the grains Simulation::freeze froze (empty when none): not in the scene, carried
  // into a model compiled again from it (ModuleSpec::carry).
  std::vector<uint8_t> frozen_by_freeze;
  std::vector<int32_t> group;
};

// Volume of a grain of radius r: a sphere's in 3D, a disk's area in 2D (disks are per unit
// thickness, as their masses).
inline double grain_volume(int dim, double r) {
  return dim == 3 ? 4.0 / 3.0 * std::numbers::pi * r * r * r : std::numbers::pi * r * r;
}

// A grain's moment of inertia over m r^2: a solid sphere's 2/5, a disk's 1/2.
inline double inertia_factor(int dim) { return dim == 3 ? 0.4 : 0.5; }

struct RunLimits {
  double max_overlap = 0.2;    // fraction of the smaller radius
  double energy_factor = 100;  // runaway when ke > energy_factor * energy_scale
  double energy_scale = 0;     // energy the scene can supply [J], computed by compile()
  // Gravity along a periodic axis supplies energy without end: by time t, at most
  // energy_per_s t + energy_per_s2 t^2 more (the work of g on the free grains' momentum).
  double energy_per_s = 0, energy_per_s2 = 0;
  int64_t check_every = 100;
  // What the scene can have supplied by time t [J].
  double energy_supply(double t) const { return energy_scale + t * (energy_per_s + t * energy_per_s2); }
};

// What a frame shows ([render] of the scene), read by the renderer; plain data, no GL here.
struct RenderSettings {
  // Largest frame: 64 Mpx, about 1 GB drawn (colour and depth buffers, the image, PNG rows).
  static constexpr int64_t kMaxPixels = int64_t{8192} * 8192;
  int width = 1280, height = 720;
  std::vector<std::string> draw{"grains", "colorbar", "time", "scalebar"};
  // flat | speed | vx | vy | vz | height | id | group | frozen; "": speed, or flat with chains or a field
  std::string color_by = "speed";
  std::string colormap = "sequential";  // sequential | diverging
  bool range_auto = true;
  double range[2] = {0, 1};
  double flat_color[3] = {0.75, 0.75, 0.78};
  double background[3] = {1, 1, 1};
  double chain_width = 0.4;  // line width at the mean normal force, in mean radii
  bool chains_above_mean = false;
  double slab_half_width = 0;  // 3D chains: only those within this distance of the slab plane (0: all)
  double slab_center[3] = {0, 0, 0};
  bool slab_center_auto = true;  // not given: the centre of the box as it is in the state drawn
  double slab_normal[3] = {0, 1, 0};
  double grain_opacity = -1;        // -1: opaque, or 0.25 in 3D when chains are drawn
  std::string field = "vorticity";  // vorticity | velocity | pressure (fluid fields)
  bool field_range_auto = true;
  double field_range[2] = {-1, 1};
  double slice_normal[3] = {0, 0, 1};         // 3D field slice: unit normal n of the plane n . x = slice_position
  double slice_position = 0;                  // [m] (an axis normal: the coordinate along that axis)
  std::string slice_component = "magnitude";  // x | y | z | magnitude (3D vector fields)
  double azimuth = 30, elevation = 25, distance = 0, fov = 30;  // 3D orbit camera [deg]; distance 0: auto
  bool target_auto = true;
  double target[3] = {0, 0, 0};
  bool periodic_images = false;
  int64_t every = 0;  // steps between frames (0: output.every)
  bool wants(const std::string& item) const;
};

// The velocity profile a run's summary gives (RunJob): slabs across `axis` (-1: none); slabs 0:
// about one largest diameter thick at the start of the run, 4 to 40.
struct VelocityProfileSpec {
  int axis = -1, component = 0, slabs = 0;
};

struct StaticCriterion {
  bool on = false;
  double force_tol = 1e-4, stress_tol = 1e-4, ke_tol = 1e-8;
};

struct Model {
  // Provenance.
  std::string scene_file, scene_name;
  // The checkpoints the scene's grains were read from (grains[].frozen_from), as found.
  std::vector<std::string> checkpoints_read;
  // The files the model was compiled from, each with what a message calls it: the scene file and
  // checkpoints_read. No output of a run (silt run's, the shell's) may overwrite them.
  std::vector<std::pair<std::string, std::string>> files_read() const;
  bool reduced_units = false;  // scene.units = "reduced": labels carry no SI units
  // A unit as this model's labels show it (keys, observables, messages): none in reduced units, and
  // a stress's or a pressure's Pa is a force per length, N/m, in 2D (`print pressure` and `get
  // box.pressure` read Pa in pack_2d).
  std::string unit_name(const std::string& si) const {
    if (reduced_units) return "";
    return dim == 2 && si == "Pa" ? "N/m" : si;
  }
  // " s", " kg", ... after a number, or nothing in reduced units (unit_name's).
  std::string unit(const char* si) const {
    const std::string name = unit_name(si);
    return name.empty() ? name : " " + name;
  }
  uint64_t scene_hash = 0;  // system_fingerprint(*this, init.frozen): checkpoints refuse other systems
  SceneDesc desc;           // what the file said (for `check`, `params`, `get`)

  // The modules the scene turns on (silt/module.hpp), in the order of the module list; core and
  // dem are always on. Parameters of modules Model does not name are in `params`.
  std::vector<std::string> modules;
  bool module_on(std::string_view name) const;
  ModuleParams params;

  int dim = 3;
  int rot = 3;  // rotational degrees of freedom per grain
  int64_t n_grains = 0, n_frozen = 0;
  // Whether two grains can touch: two free ones, or a frozen one (with a free one, where any moves).
  bool pairs_form() const { return n_grains - n_frozen >= 2 || n_frozen > 0; }
  std::vector<std::string> group_names;
  GrainInit init;
  double r_min = 0, r_max = 0, r_mean = 0, m_min = 0, m_mean = 0;
  double a_max = 0;  // largest diameter, the length unit of Peyneau's criteria
  double m_a = 0;    // mass of a grain of diameter a_max (at the free grains' mean density): the
                     // mass unit of the inertial number (Peyneau 2009 sec. 5.3.3)

  Box box;
  std::array<int64_t, 3> cells{0, 0, 0};  // cells of a grid per axis (a fluid's; 0: no grid)
  int64_t n_cells() const { return cells[0] * cells[1] * (dim == 3 ? cells[2] : 1); }  // 0: no grid
  // Whether a stage reads the pair forces at the end of every step (a controlled box does), so
  // that contact_forces stores them even in the steps whose end nothing sees.
  bool pair_forces_every_step = false;
  BoxControl box_control;
  ShearControl shear;
  Preparation prepare;
  std::vector<Wall> walls;
  ContactParams contact;
  // Materials (dem/materials.hpp): one per [[grains]] group, the contact law of every pair of
  // groups, [g_i * G + g_j], and of every wall with every group, [w * G + g]. Grain pairs use
  // `contact` alone when every group is of the scene's material (pair_contact empty).
  std::vector<Material> materials;
  std::vector<ContactParams> pair_contact, wall_contact;
  // Whether a grain-grain contact may carry a tangential force (some pair has friction).
  bool pair_friction() const;
  Vec3 gravity = Vec3::Zero();  // steerable
  // Component a of the weight of a grain of inverse mass inv_m (none on a frozen grain): what the
  // state's force sums leave out of a grain's total force.
  double weight(double inv_m, bool frozen, int a) const { return frozen ? 0.0 : gravity[a] / inv_m; }

  // Time stepping.
  double dt = 0;  // steerable
  // The step when the scene gives neither run.dt nor run.dt_over_tc: the smallest that the
  // enabled modules propose (propose_dt: the DEM 0.02 t_c, a fluid its own step).
  double default_dt = 0;
  void propose_dt(double step) { default_dt = default_dt > 0 ? std::min(default_dt, step) : step; }
  double t_contact = 0;  // contact time of the lightest, stiffest pair [s]: the given t_c
                         // (spring_dashpot), else the elastic time pi sqrt(m*/k) (Hertz: at
                         // contact.hertz_ref_overlap)
  double zeta_max = 0;   // damping ratio of that pair
  // That pair: the scene's law between its two lightest grains or, where the groups have laws of
  // their own, the pair of groups whose collision is the shortest (group_i, group_j; -1 for the
  // scene's law); where no two grains can touch, a grain's collision with a wall (wall >= 0).
  struct ContactTimePair {
    ContactParams law;
    double m_eff = 0, r_eq = 0;
    int group_i = -1, group_j = -1, wall = -1;
  };
  ContactTimePair tc_pair;
  // The stiffness of kappa (Peyneau eq. 1.32-1.33): k_n, or E~ for Hertz, of the softest and the
  // stiffest law that grain pairs use (walls apart).
  double kappa_stiffness_min = 0, kappa_stiffness_max = 0;
  std::string kappa_softest_key;  // the key that sets the softest (contact.k_n, grains[1].k_n, ...)
  double dt_stable = 0;           // velocity-Verlet stability limit of the fastest contact mode [s]
  // Whether that mode is a tangential spring's (friction, k_t / k_n above 1/3 for disks, 2/7 for
  // spheres), and the mode's stiffness (a tangential one's k_t (1 + m r^2 / I)) and reduced mass.
  bool dt_stable_tangential = false;
  double k_stable = 0, m_eff_stable = 0;
  // Whether grains of groups g_i and g_j can touch, [g_i * G + g_j] (two free grains, or a free
  // one and a frozen one), beside pair_contact.
  std::vector<char> pair_meets;
  double m_eff_min = 0;   // lightest reduced mass of a possible contact [kg]
  double k_max = 0;       // stiffest normal contact (Hertz: at the largest allowed overlap)
  int64_t run_steps = 0;  // from [run] (steps or time / dt), overridable on the command line
  double run_time = -1;   // [run] time when given [s]: the run length of an adaptive step
  // Whether [run] gives a length (steps = 0 is one: the preparation alone).
  bool gives_run_length() const { return run_time >= 0 || desc.has("run.steps"); }
  StaticCriterion until_static;
  // Runs end when every enabled module's steady-state test holds (ModuleSpec::steady; the
  // fluid's run.stop_when_steady), tested every limits.check_every steps.
  bool stop_when_steady = false;

  double skin = 0;  // Verlet skin [m]
  // Gap within which every pair must stay listed: 0 for contacts alone, the lubrication range
  // h_max with a paste. A list is rebuilt before the skin left beyond it is used up.
  double pair_gap = 0;
  // A module solves the grains' velocities every step (the paste's resistance-matrix solve): the
  // DEM only drifts the grains and computes contact forces, without kicks or an energy check, and
  // the box lengths follow the solved strain rates without a box kick.
  bool velocities_solved = false;
  // The time step is chosen every step by a module (the paste's adaptive step): runs of a given
  // time end at the first step boundary at or past it, not after a step count.
  bool adaptive_dt = false;
  // How `silt check` and the shell name the step of a module that chooses it (adaptive_dt): a
  // paste's "fixed time step 0.01 s" or "adaptive time step: the first 0.001 s". Empty: an adaptive
  // step from dt.
  std::string dt_text;
  // The key that sets the step the DEM's failure reports advise lowering: run.dt, or that of the
  // module choosing the step (a paste's lubrication.dt_max).
  std::string dt_key = "run.dt";
  // The key that bounds how far a step moves the grains, when it is not the step's own: a paste's
  // lubrication.drift_max (its adaptive step is at most it over the fastest grain); overlap
  // reports advise it. Empty: dt_key.
  std::string drift_key;
  // Per-pair force arrays of modules (P*D, the layout of pair_f: force on i from j) that count
  // in the grains' stress besides the contact forces: the lubrication forces of a paste.
  std::vector<uint16_t> pair_stress_fields;
  // Whether the grains' stress has its kinetic term sum m v (x) v: not where velocities are
  // solved without inertia (a quasi-static paste), where they carry no momentum.
  bool kinetic_stress = true;
  double contact_skin = 0;  // gap below which listed pairs are tested every step [m]; >= skin: all
  bool sort_grains = true;  // reorder grains by cell at list builds (N > kSortMin)
  static constexpr int64_t kSortMin = 1024;
  // Whether the box deforms (controlled lengths, or simple shear): the grains then follow its
  // affine flow.
  bool deforming_box() const { return box_control.on || shear.on; }
  // Largest centre distance at which two grains interact, 2 r_max + skin: the reach of the
  // neighbour list, of its cells, and the smallest half period a box may have.
  double interaction_range() const { return 2 * r_max + skin; }

  RenderSettings render;

  std::vector<std::string> observe;  // stats columns
  int64_t sample_every = 100;
  VelocityProfileSpec profile;
  RunLimits limits;
};

// The number of steps of dt in a run of `time` [s]: ceil(time / dt), a last step that would
// overshoot by less than 1e-9 dt not counted; -1 when it is more than kMaxRunSteps (the bound
// run.steps and --steps take too). The one conversion of a run length in time to steps (scene
// files, --time, the shell's `run Ts`).
int64_t steps_in(double time, double dt);
// Why steps_in refused a run: "too long, more than 9e18 steps of DT s", for every reader's message.
std::string too_many_steps(double dt);

// Compile a validated scene into a Model. Throws SceneError with the location of the value that
// makes the scene impossible to simulate (bad geometry, overlaps, unstable time step, ...).
Model compile(const SceneDesc& desc);

// Apply a change a user typed (`set KEY VALUE`) to a scene: checked like the file's values, it
// replaces the keys it is an alternative to (run.dt replaces run.dt_over_tc, gravity.vector
// gravity.magnitude and gravity.angle, one shear mode the others). change.key is canonical
// ("grains[0].radius"). Errors, and those compile() later finds in this value, are located at
// `where` (e.g. "set run.dt") instead of a file position. Throws SceneError.
void apply_change(SceneDesc& desc, const Override& change, const std::string& where);

// Change one value of a compiled model between two steps ("live steering"). Only keys marked
// steerable in the schema are accepted (gravity, friction, time step, imposed pressure, render
// settings, ...): the scene is recompiled with the new value and the steerable parts are taken
// over. Returns "" on success, else the reason (not steerable, out of range, unstable, ...).
// `scene`, when given, is the scene as it reads with the change (a shell's file with the values
// typed since it was loaded); else the model's own scene with the change. They differ where a key
// has alternatives: `set gravity.vector V` then `set gravity.magnitude G` gives the file's
// gravity.angle back with the scene, where the model's own scene has lost it to the vector.
std::string steer(Model& m, const Override& change, const SceneDesc* scene = nullptr);

// The pressure of the dry compression that prepares a packing (prepare.compress): the
// preparation's own, else the box's.
inline double preparation_pressure(const Model& m) {
  return m.prepare.pressure > 0 ? m.prepare.pressure : m.box_control.pressure;
}

// Human-readable description of a compiled model (`silt check`).
std::string describe(const Model& m);
// The step of a model whose step a module chooses (adaptive_dt), in words: dt_text, or an adaptive
// step from dt.
std::string step_text(const Model& m);

// Identity of the system a checkpoint belongs to: dimension, periodicity, the number of walls and
// every grain's size, mass and group, with `frozen` (by grain id) as its frozen flags. Run
// parameters (friction, time step, pressure, ...) are not part of it, so a prepared packing can be
// restored and run with other values.
uint64_t system_fingerprint(const Model& m, const std::vector<uint8_t>& frozen);

// Stability bound of velocity Verlet for a damped oscillator of pulsation w0 and damping ratio
// zeta: dt < (2/w0)(sqrt(1 + zeta^2) - zeta).
double verlet_stability_limit(double w0, double zeta);

}  // namespace silt
