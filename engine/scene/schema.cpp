// The single source of truth for every scene key (DESIGN.md "Parameters, scene files, errors").
// The reader validates against it, compile() reads defaults from it, `silt params` and the
// README's parameter table print it.
#include <cmath>
#include <sstream>

#include "silt/scene.hpp"

namespace silt {
namespace {

constexpr double kInf = 1e308;
Range any() { return {}; }
Range positive() { return {0.0, kInf, true, false}; }
Range non_negative() { return {0.0, kInf, false, false}; }
Range closed(double lo, double hi) { return {lo, hi, false, false}; }
Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
Range closed_open(double lo, double hi) { return {lo, hi, false, true}; }

using S = std::vector<std::string>;

std::vector<KeySpec> build_schema() {
  using K = KeyType;
  std::vector<KeySpec> s = {
      // ---- scene
      {"scene.name", K::kString, Value(std::string()), any(), "", false, {}, "A name for the scene, shown in outputs."},
      {"scene.dimension", K::kInt, Value(int64_t{3}), closed(2, 3), "", false, {}, "2: disks in the x-y plane; 3: spheres."},
      {"scene.seed", K::kInt, Value(int64_t{1}), closed(0, 4.6e18), "", false, {}, "Seed of every random draw (radii, placement, velocities)."},
      // ---- domain
      {"domain.lo", K::kRealList, std::nullopt, any(), "m", false, {}, "Lower corner of the domain (one entry per dimension)."},
      {"domain.hi", K::kRealList, std::nullopt, any(), "m", false, {}, "Upper corner of the domain."},
      {"domain.periodic", K::kBoolList, std::nullopt, any(), "", false, {}, "Periodic flag per direction (default: none)."},
      // ---- stress-controlled periodic box
      {"box.pressure", K::kReal, std::nullopt, positive(), "Pa", true, {}, "Imposed pressure on the controlled box lengths (Peyneau 2009 eq. 3.11); absent: fixed box."},
      {"box.controlled", K::kBoolList, std::nullopt, any(), "", false, {}, "Which box lengths follow the pressure (default: every periodic one)."},
      {"box.mass_factor", K::kReal, Value(1.0), positive(), "", true, {}, "Box mass M in units of the total grain mass N m (Peyneau: M = N m), for the box lengths and a stress-controlled shear."},
      // ---- simple shear (Lees-Edwards, flow along x, gradient along y)
      {"shear.rate", K::kReal, std::nullopt, any(), "1/s", true, {}, "Imposed shear rate gammadot of the flow v_x = gammadot y (liquid regime)."},
      {"shear.inertial_number", K::kReal, std::nullopt, positive(), "", true, {}, "Imposed inertial number I = gammadot sqrt(m / (a^(d-2) P)) (Peyneau eq. 1.30), with P = box.pressure."},
      {"shear.stress", K::kReal, std::nullopt, any(), "Pa", true, {}, "Imposed shear stress tau = -sigma_xy (solid regime, Peyneau eq. 3.12): gammadot follows it."},
      // ---- preparation
      {"prepare.compress", K::kBool, Value(false), any(), "", false, {}, "Before the run, compress the grains isotropically at box.pressure (every periodic length controlled, no shear) until static: Peyneau's procedure O."},
      {"prepare.max_steps", K::kInt, Value(int64_t{2000000}), closed(1, 4.6e18), "", false, {}, "Longest preparation; the run then starts from where it got, with a warning."},
      // ---- gravity
      {"gravity.vector", K::kRealList, std::nullopt, any(), "m/s^2", true, {}, "Gravity vector; or give gravity.magnitude and gravity.angle."},
      {"gravity.magnitude", K::kReal, std::nullopt, non_negative(), "m/s^2", true, {}, "|g|, pointing along -z (3D) or -y (2D) before the tilt."},
      {"gravity.angle", K::kReal, Value(0.0), closed(-90, 90), "deg", true, {}, "Chute angle: gravity tilted from -z (-y in 2D) toward +x."},
      // ---- contact law
      {"contact.model", K::kString, std::nullopt, any(), "", false, S{"spring_dashpot", "hooke", "hertz", "linear"},
       "Normal law: spring_dashpot (Izard 2014, from restitution and contact time), hooke (LAMMPS gran/hooke), hertz (Peyneau 2009 ch. 3), linear (k_n with damping ratio)."},
      {"contact.restitution", K::kReal, std::nullopt, open_closed(0, 1), "", false, {}, "spring_dashpot: dry normal restitution coefficient e (Izard eq. 3.16)."},
      {"contact.contact_time", K::kReal, std::nullopt, positive(), "s", false, {}, "spring_dashpot: contact duration t_c (Izard eq. 3.17)."},
      {"contact.k_n", K::kReal, std::nullopt, positive(), "N/m", false, {}, "hooke, linear: normal stiffness."},
      {"contact.gamma_n", K::kReal, Value(0.0), non_negative(), "1/s", false, {}, "hooke: normal damping rate; the dashpot is m* gamma_n (LAMMPS convention)."},
      {"contact.damping", K::kReal, Value(0.0), closed(0, 10), "", false, {}, "hertz, linear: dashpot as a fraction zeta of critical damping, 2 zeta sqrt(m* K_N)."},
      {"contact.young_modulus", K::kReal, std::nullopt, positive(), "Pa", false, {}, "hertz: Young modulus E."},
      {"contact.poisson_ratio", K::kReal, Value(0.3), closed_open(-1, 0.5), "", false, {}, "hertz: Poisson ratio nu; E~ = E / (1 - nu^2)."},
      {"contact.hertz_ref_overlap", K::kReal, Value(0.01), open_closed(0, 0.5), "", false, {}, "hertz: overlap (fraction of the reduced radius) at which contact time and time step are quoted."},
      {"contact.clip_attractive", K::kBool, Value(false), any(), "", false, {}, "Clip the normal force at zero so that the dashpot never attracts (Izard eq. 3.13)."},
      {"contact.friction", K::kReal, Value(0.0), closed(0, 10), "", true, {}, "Coulomb friction coefficient mu between grains; 0 is frictionless."},
      {"contact.kt_over_kn", K::kReal, Value(2.0 / 7.0), closed(0, 10), "", false, {}, "Tangential spring stiffness k_t / k_n."},
      {"contact.tangential_damping", K::kReal, Value(0.0), closed(0, 10), "", false, {}, "Tangential dashpot as a fraction of critical damping, 2 zeta_t sqrt(m* k_t) (LAMMPS gamma_t; Peyneau's e_T = 0 needs a strong one)."},
      // ---- walls
      {"walls[].point", K::kRealList, std::nullopt, any(), "m", false, {}, "A point of the planar wall."},
      {"walls[].normal", K::kRealList, std::nullopt, any(), "", false, {}, "Normal of the wall, pointing into the domain."},
      {"walls[].friction", K::kReal, std::nullopt, closed(0, 10), "", true, {}, "Grain-wall friction (default: contact.friction)."},
      // ---- grains
      {"grains[].name", K::kString, Value(std::string()), any(), "", false, {}, "Name of the group."},
      {"grains[].count", K::kInt, std::nullopt, closed(1, 1e9), "", false, {}, "Number of grains (lattice: default every site of the region)."},
      {"grains[].radius", K::kReal, std::nullopt, positive(), "m", false, {}, "Monodisperse radius."},
      {"grains[].radius_min", K::kReal, std::nullopt, positive(), "m", false, {}, "Radii uniform in [radius_min, radius_max]."},
      {"grains[].radius_max", K::kReal, std::nullopt, positive(), "m", false, {}, "Radii uniform in [radius_min, radius_max]."},
      {"grains[].radii", K::kRealList, std::nullopt, positive(), "m", false, {}, "Discrete radii (bidisperse or more), with volume_fractions."},
      {"grains[].volume_fractions", K::kRealList, std::nullopt, closed(0, 1), "", false, {}, "Fraction of the grain volume held by each of radii."},
      {"grains[].radius_list", K::kRealList, std::nullopt, positive(), "m", false, {}, "Explicit radius of every grain."},
      {"grains[].density", K::kReal, Value(1.0), positive(), "kg/m^3", false, {}, "Grain density (per area for 2D disks)."},
      {"grains[].frozen", K::kBool, Value(false), any(), "", false, {}, "Frozen grains never move (rough bases); their velocity still enters contacts."},
      {"grains[].placement", K::kString, Value(std::string("random")), any(), "", false, S{"lattice", "random", "explicit"}, "How grains are placed."},
      {"grains[].lattice", K::kString, Value(std::string("sc")), any(), "", false, S{"sc", "hex", "fcc"}, "Lattice: sc (square/cubic), hex (2D triangular), fcc (3D)."},
      {"grains[].spacing", K::kReal, std::nullopt, positive(), "m", false, {}, "Lattice spacing (nearest sites)."},
      {"grains[].lattice_origin", K::kRealList, std::nullopt, any(), "m", false, {}, "A site of the lattice (default: the origin); sites fill the region from there."},
      {"grains[].region_lo", K::kRealList, std::nullopt, any(), "m", false, {}, "Lower corner of the placement region (default: domain.lo)."},
      {"grains[].region_hi", K::kRealList, std::nullopt, any(), "m", false, {}, "Upper corner of the placement region (default: domain.hi)."},
      {"grains[].positions", K::kRealMatrix, std::nullopt, any(), "m", false, {}, "Explicit centres, one list per grain."},
      {"grains[].velocity", K::kString, Value(std::string("zero")), any(), "", false, S{"zero", "gaussian", "explicit"}, "Initial velocities."},
      {"grains[].temperature", K::kReal, std::nullopt, non_negative(), "J", false, {}, "gaussian: kinetic temperature m <v_x^2> (zero total momentum)."},
      {"grains[].velocities", K::kRealMatrix, std::nullopt, any(), "m/s", false, {}, "explicit: one velocity per grain."},
      {"grains[].angular_velocities", K::kRealMatrix, std::nullopt, any(), "rad/s", false, {}, "explicit: one angular velocity per grain (a 1-list in 2D)."},
      // ---- neighbour search
      {"neighbor.skin", K::kReal, std::nullopt, positive(), "m", false, {}, "Verlet skin (default: 0.1 largest diameter); lists rebuilt when a grain moved skin/2."},
      {"neighbor.contact_skin", K::kReal, std::nullopt, non_negative(), "m", false, {}, "Listed pairs closer than this gap are the ones tested for contact each step, re-selected when grains have moved half of it (default: skin/5; 0 tests every listed pair). Changes the cost, never the result."},
      {"neighbor.sort", K::kBool, Value(true), any(), "", false, {}, "Keep grains in cell order at each list build when there are more than 1024 (cache locality; ids are kept)."},
      // ---- run
      {"run.dt", K::kReal, std::nullopt, positive(), "s", true, {}, "Time step."},
      {"run.dt_over_tc", K::kReal, std::nullopt, open_closed(0, 1), "", true, {}, "Time step as a fraction of the contact time (default 0.02)."},
      {"run.steps", K::kInt, std::nullopt, closed(0, 9e18), "", false, {}, "Run length in steps."},
      {"run.time", K::kReal, std::nullopt, non_negative(), "s", false, {}, "Run length in simulated time."},
      {"run.stop_when_static", K::kBool, Value(false), any(), "", false, {}, "Stop when the packing is in equilibrium (forces, stresses and kinetic energy below the tolerances)."},
      {"run.static_force_tol", K::kReal, Value(1e-4), positive(), "", false, {}, "Equilibrium: largest net force on a grain / (a^(d-1) P)."},
      {"run.static_stress_tol", K::kReal, Value(1e-4), positive(), "", false, {}, "Equilibrium: |sigma_aa / P - 1| on controlled axes."},
      {"run.static_ke_tol", K::kReal, Value(1e-8), positive(), "", false, {}, "Equilibrium: translational kinetic energy per grain / (a^d P)."},
      // ---- output
      {"output.observe", K::kStringList, Value(std::vector<std::string>{"t", "step", "ke"}), any(), "", false, {}, "Observables written to the stats file."},
      {"output.every", K::kInt, Value(int64_t{100}), closed(1, 1e12), "", false, {}, "Sample every N steps."},
      // ---- render: what a frame shows (silt run --frames)
      {"render.width", K::kInt, Value(int64_t{1280}), closed(16, 16384), "px", false, {}, "Frame width (width x height at most 64 Mpx, e.g. 8192 x 8192)."},
      {"render.height", K::kInt, Value(int64_t{720}), closed(16, 16384), "px", false, {}, "Frame height."},
      {"render.draw", K::kStringList, Value(std::vector<std::string>{"grains", "colorbar", "time", "scalebar"}), any(), "", true,
       S{"grains", "chains", "field", "colorbar", "time", "scalebar", "box"}, "What frames show."},
      {"render.color_by", K::kString, std::nullopt, any(), "", true,
       S{"flat", "speed", "vx", "vy", "vz", "height", "id", "group", "frozen"}, "Quantity that colours the grains (default: speed, or flat when chains or a field are drawn)."},
      {"render.colormap", K::kString, Value(std::string("sequential")), any(), "", true, S{"sequential", "diverging"}, "Colormap of the grains (assets/*.csv)."},
      {"render.range", K::kRealList, std::nullopt, any(), "", true, {}, "Colour range [lo, hi] of the grain quantity (default: automatic)."},
      {"render.flat_color", K::kRealList, Value(std::vector<double>{0.75, 0.75, 0.78}), closed(0, 1), "", true, {}, "RGB of grains when color_by = flat (and of frozen grains)."},
      {"render.background", K::kRealList, Value(std::vector<double>{1, 1, 1}), closed(0, 1), "", true, {}, "RGB of the background."},
      {"render.chain_width", K::kReal, Value(0.4), open_closed(0, 10), "", true, {}, "Force-chain width at the mean normal force, in mean grain radii; proportional to the force, at most a mean grain diameter."},
      {"render.chains_above_mean", K::kBool, Value(false), any(), "", true, {}, "Draw only contacts carrying more than the mean normal force."},
      {"render.slab_half_width", K::kReal, Value(0.0), non_negative(), "m", true, {}, "3D: draw only the chains and grains within this distance of the slab plane (0: all)."},
      {"render.slab_center", K::kRealList, std::nullopt, any(), "m", true, {}, "3D: a point of the chain slab (default: domain centre)."},
      {"render.slab_normal", K::kRealList, std::nullopt, any(), "", true, {}, "3D: normal of the chain slab (default: y)."},
      {"render.grain_opacity", K::kReal, std::nullopt, open_closed(0, 1), "", true, {}, "Grain opacity (default: 1, or 0.25 in 3D with chains)."},
      {"render.field", K::kString, Value(std::string("vorticity")), any(), "", true, S{"vorticity", "velocity", "pressure"}, "Fluid field drawn with draw = field."},
      {"render.field_range", K::kRealList, std::nullopt, any(), "", true, {}, "Colour range of the field (default: symmetric about zero, from its extremes)."},
      {"render.slice_axis", K::kString, Value(std::string("z")), any(), "", true, S{"x", "y", "z"}, "3D: normal of the field slice, along an axis."},
      {"render.slice_normal", K::kRealList, std::nullopt, any(), "", true, {}, "3D: normal of the field slice, any direction (instead of slice_axis)."},
      {"render.slice_position", K::kReal, std::nullopt, any(), "m", true, {}, "3D: the slice is the plane n . x = slice_position, n the unit normal (default: through the domain centre)."},
      {"render.slice_component", K::kString, Value(std::string("magnitude")), any(), "", true, S{"x", "y", "z", "magnitude"}, "3D: component of a vector field on the slice."},
      {"render.camera.azimuth", K::kReal, Value(30.0), closed(-360, 360), "deg", true, {}, "3D orbit camera: azimuth about z from +x."},
      {"render.camera.elevation", K::kReal, Value(25.0), closed(-89, 89), "deg", true, {}, "3D orbit camera: elevation above the x-y plane."},
      {"render.camera.distance", K::kReal, Value(0.0), non_negative(), "m", true, {}, "3D orbit camera: distance to the target (0: frame the domain)."},
      {"render.camera.target", K::kRealList, std::nullopt, any(), "m", true, {}, "3D orbit camera: point looked at (default: domain centre)."},
      {"render.camera.fov", K::kReal, Value(30.0), closed(1, 120), "deg", true, {}, "3D: vertical field of view."},
      {"render.periodic_images", K::kBool, Value(false), any(), "", true, {}, "Also draw the periodic images of grains that cross the box."},
      {"render.every", K::kInt, std::nullopt, closed(1, 1e12), "", true, {}, "Steps between frames (default: output.every)."},
      // ---- limits: where the engine stops instead of producing nonsense
      {"limits.max_overlap", K::kReal, Value(0.2), open_closed(0, 1), "", false, {}, "Stop when an overlap exceeds this fraction of the smaller radius."},
      {"limits.energy_factor", K::kReal, Value(100.0), open_closed(1, 1e12), "", false, {}, "Stop when kinetic energy exceeds this factor times the energy the scene can supply."},
      {"limits.check_every", K::kInt, Value(int64_t{100}), closed(1, 1e9), "", false, {}, "Steps between energy checks (and saved restart points)."},
  };
  return s;
}

}  // namespace

const std::vector<KeySpec>& scene_schema() {
  static const std::vector<KeySpec> schema = build_schema();
  return schema;
}

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  if (lo_open ? !(x > lo) : !(x >= lo)) return false;
  if (hi_open ? !(x < hi) : !(x <= hi)) return false;
  return true;
}

static std::string num(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

std::string Range::str() const {
  const bool has_lo = lo > -1e307, has_hi = hi < 1e307;
  if (has_lo && has_hi) return (lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
  if (has_lo) return (lo_open ? "> " : ">= ") + num(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + num(hi);
  return "any";
}

const char* key_type_name(KeyType t) {
  switch (t) {
    case KeyType::kBool: return "boolean";
    case KeyType::kInt: return "integer";
    case KeyType::kReal: return "number";
    case KeyType::kString: return "string";
    case KeyType::kRealList: return "list of numbers";
    case KeyType::kRealMatrix: return "list of lists of numbers";
    case KeyType::kBoolList: return "list of booleans";
    case KeyType::kStringList: return "list of strings";
  }
  return "?";
}

std::string schema_markdown() {
  std::ostringstream o;
  o << "| key | type | default | range | unit | live | meaning |\n|---|---|---|---|---|---|---|\n";
  for (const KeySpec& k : scene_schema()) {
    std::string doc = k.doc;
    if (!k.choices.empty()) {
      doc += " One of:";
      for (const auto& c : k.choices) doc += " `" + c + "`";
      doc += ".";
    }
    const bool numeric = k.type == KeyType::kInt || k.type == KeyType::kReal || k.type == KeyType::kRealList;
    o << "| `" << k.path << "` | " << key_type_name(k.type) << " | "
      << (k.def ? "`" + value_to_string(*k.def) + "`" : std::string("-")) << " | "
      << (numeric ? k.range.str() : std::string("")) << " | " << k.unit << " | "
      << (k.steerable ? "yes" : "") << " | " << doc << " |\n";
  }
  return o.str();
}

}  // namespace silt
