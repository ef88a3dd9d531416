// The DEM's scene keys: contact law, walls, grains, neighbour search.
#include "dem/module.hpp"
#include "silt/text.hpp"

namespace silt::dem {

std::vector<KeySpec> dem_keys() {
  using K = KeyType;
  using S = std::vector<std::string>;
  // clang-format off
  std::vector<KeySpec> s = {
      // ---- contact
      {"contact.model", K::kString, std::nullopt, Range::any(), "", false, S{"spring_dashpot", "hooke", "hertz", "linear"},
       "Normal law: spring_dashpot (Izard 2014, from restitution and contact time), hooke (LAMMPS gran/hooke), hertz (Peyneau 2009 ch. 3), linear (k_n with damping ratio)."},
      {"contact.restitution", K::kReal, std::nullopt, Range::open_closed(0, 1), "", false, {}, "spring_dashpot: dry normal restitution coefficient e (Izard eq. 3.16)."},
      {"contact.contact_time", K::kReal, std::nullopt, Range::positive(), "s", false, {}, "spring_dashpot: contact duration t_c (Izard eq. 3.17)."},
      {"contact.k_n", K::kReal, std::nullopt, Range::positive(), "N/m", false, {}, "hooke, linear: normal stiffness; may be left out where every group and wall gives its own (or the wall is rigid)."},
      {"contact.gamma_n", K::kReal, Value(0.0), Range::non_negative(), "1/s", false, {}, "hooke: normal damping rate; the dashpot is m* gamma_n (LAMMPS convention)."},
      {"contact.damping", K::kReal, Value(0.0), Range::closed(0, 10), "", false, {}, "hertz, linear: dashpot as a fraction zeta of critical damping, 2 zeta sqrt(m* K_N)."},
      {"contact.young_modulus", K::kReal, std::nullopt, Range::positive(), "Pa", false, {}, "hertz: Young modulus E; may be left out where every group and wall gives its own (or the wall is rigid)."},
      {"contact.poisson_ratio", K::kReal, Value(0.3), Range::open(-1, 0.5), "", false, {}, "hertz: Poisson ratio nu; E~ = E / (1 - nu^2)."},
      {"contact.hertz_ref_overlap", K::kReal, Value(0.01), Range::open_closed(0, 0.5), "", false, {}, "hertz: overlap at which contact time and time step are quoted, a fraction of R_eq, 2/R_eq = 1/r_i + 1/r_j (Peyneau eq. 1.22: the radius itself for two like grains, not half of it)."},
      {"contact.clip_attractive", K::kBool, Value(false), Range::any(), "", false, {}, "Clip the normal force at zero so that the dashpot never attracts (Izard eq. 3.13)."},
      {"contact.friction", K::kReal, Value(0.0), Range::closed(0, 10), "", true, {}, "Coulomb friction coefficient mu between grains; 0 is frictionless."},
      {"contact.kt_over_kn", K::kReal, Value(2.0 / 7.0), Range::closed(0, 10), "", false, {}, "Tangential spring stiffness k_t / k_n."},
      {"contact.tangential_damping", K::kReal, Value(0.0), Range::closed(0, 10), "", false, {}, "Tangential dashpot as a fraction of critical damping, 2 zeta_t sqrt(m* k_t) (LAMMPS gamma_t; Peyneau's e_T = 0 needs a strong one)."},
      // ---- walls
      {"walls[].point", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "A point of the planar wall."},
      {"walls[].normal", K::kRealList, std::nullopt, Range::any(), "", false, {}, "Normal of the wall, pointing into the domain."},
      {"walls[].friction", K::kReal, std::nullopt, Range::closed(0, 10), "", true, {}, "Grain-wall friction (default: the friction of the grain's group, grains[].friction, else contact.friction)."},
      {"walls[].young_modulus", K::kReal, std::nullopt, Range::positive(), "Pa", false, {}, "hertz: the wall's Young modulus (default: the grains'); the pair's E~ is 2 / ((1 - nu_g^2)/E_g + (1 - nu_w^2)/E_w)."},
      {"walls[].poisson_ratio", K::kReal, std::nullopt, Range::open(-1, 0.5), "", false, {}, "hertz: the wall's Poisson ratio (default: contact.poisson_ratio)."},
      {"walls[].rigid", K::kBool, Value(false), Range::any(), "", false, {}, "hertz, hooke, linear: a wall that does not deform (Hertz: E~ doubles against it; springs: twice the grain's k_n, the series rule's limit)."},
      {"walls[].k_n", K::kReal, std::nullopt, Range::positive(), "N/m", false, {}, "hooke, linear: the wall's spring, in series with the grain's (default: contact.k_n)."},
      // ---- grains
      {"grains[].name", K::kString, Value(std::string()), Range::any(), "", false, {}, "Name of the group."},
      {"grains[].count", K::kInt, std::nullopt, Range::closed(1, 1e9), "", false, {}, "Number of grains (lattice: default every site of the region)."},
      {"grains[].radius", K::kReal, std::nullopt, Range::positive(), "m", false, {}, "Monodisperse radius."},
      {"grains[].radius_min", K::kReal, std::nullopt, Range::positive(), "m", false, {}, "Radii uniform in [radius_min, radius_max]."},
      {"grains[].radius_max", K::kReal, std::nullopt, Range::positive(), "m", false, {}, "Radii uniform in [radius_min, radius_max]."},
      {"grains[].radii", K::kRealList, std::nullopt, Range::positive(), "m", false, {}, "Discrete radii (bidisperse or more), with volume_fractions."},
      {"grains[].volume_fractions", K::kRealList, std::nullopt, Range::closed(0, 1), "", false, {}, "Fraction of the grain volume held by each of radii."},
      {"grains[].radius_list", K::kRealList, std::nullopt, Range::positive(), "m", false, {}, "Explicit radius of every grain."},
      {"grains[].density", K::kReal, Value(1.0), Range::positive(), "kg/m^3", false, {}, "Grain density (per area for 2D disks)."},
      {"grains[].young_modulus", K::kReal, std::nullopt, Range::positive(), "Pa", false, {}, "hertz: the group's Young modulus (default: contact.young_modulus); mixed with another's as for walls."},
      {"grains[].poisson_ratio", K::kReal, std::nullopt, Range::open(-1, 0.5), "", false, {}, "hertz: the group's Poisson ratio (default: contact.poisson_ratio)."},
      {"grains[].k_n", K::kReal, std::nullopt, Range::positive(), "N/m", false, {}, "hooke, linear: the group's spring; two groups' in series 2 k_i k_j / (k_i + k_j) (default: contact.k_n)."},
      {"grains[].friction", K::kReal, std::nullopt, Range::closed(0, 10), "", true, {}, "The group's friction coefficient; between two groups the smaller (default: contact.friction)."},
      {"grains[].frozen", K::kBool, Value(false), Range::any(), "", false, {}, "Frozen grains never move (rough bases); their velocity still enters contacts."},
      {"grains[].frozen_from", K::kString, std::nullopt, Range::any(), "", false, {}, "A checkpoint of any scene of the same dimension: its grains within region_lo/region_hi, frozen, make this group (a dense rough base made by a pour); relative paths from the scene's folder."},
      {"grains[].placement", K::kString, Value(std::string("random")), Range::any(), "", false, S{"lattice", "random", "explicit"}, "How grains are placed."},
      {"grains[].lattice", K::kString, Value(std::string("sc")), Range::any(), "", false, S{"sc", "hex", "fcc"}, "Lattice: sc (square/cubic), hex (2D triangular), fcc (3D)."},
      {"grains[].spacing", K::kReal, std::nullopt, Range::positive(), "m", false, {}, "Lattice spacing (nearest sites)."},
      {"grains[].lattice_origin", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "A site of the lattice (default: the origin); sites fill the region from there."},
      {"grains[].region_lo", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "Lower corner of the placement region (default: domain.lo); the region is its intersection with the domain."},
      {"grains[].region_hi", K::kRealList, std::nullopt, Range::any(), "m", false, {}, "Upper corner of the placement region (default: domain.hi); the region is its intersection with the domain."},
      {"grains[].positions", K::kRealMatrix, std::nullopt, Range::any(), "m", false, {}, "Explicit centres, one list per grain."},
      {"grains[].velocity", K::kString, Value(std::string("zero")), Range::any(), "", false, S{"zero", "gaussian", "explicit"}, "Initial velocities."},
      {"grains[].temperature", K::kReal, std::nullopt, Range::non_negative(), "J", false, {}, "gaussian: kinetic temperature m <v_x^2> (zero total momentum)."},
      {"grains[].velocities", K::kRealMatrix, std::nullopt, Range::any(), "m/s", false, {}, "explicit: one velocity per grain."},
      {"grains[].angular_velocities", K::kRealMatrix, std::nullopt, Range::any(), "rad/s", false, {}, "explicit: one angular velocity per grain (a 1-list in 2D)."},
      // ---- neighbor
      {"neighbor.skin", K::kReal, std::nullopt, Range::positive(), "m", false, {}, "Verlet skin (default: 0.1 largest diameter); lists rebuilt when a grain moved skin/2."},
      {"neighbor.contact_skin", K::kReal, std::nullopt, Range::non_negative(), "m", false, {}, "Listed pairs closer than this gap are the ones tested for contact each step, re-selected when grains have moved half of it (default: skin/5; 0 tests every listed pair). Changes the cost, never the result."},
      {"neighbor.sort", K::kBool, Value(true), Range::any(), "", false, {}, "Keep grains in cell order at each list build when there are more than 1024 (cache locality; ids are kept)."},
  };
  // clang-format on
  for (KeySpec& k : s) {
    if (k.path == "neighbor.skin") k.computed = [](const Model& m) { return format_number(m.skin); };
    if (k.path == "neighbor.contact_skin") k.computed = [](const Model& m) { return format_number(m.contact_skin); };
  }
  return s;
}

}  // namespace silt::dem
