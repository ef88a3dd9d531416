// The DEM's observables (INTERFACE.md): energies, packing, coordination, stress and fabric, grain
// and wall values.
#include <cmath>
#include <limits>

#include "dem/module.hpp"

namespace silt::dem {
namespace {

using Ctx = ObservableContext;
using Args = ObservableArgs;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// An observable read off a part of the measurements (measure_part: a pass over grains or
// contacts).
template <class F>
ObservableSpec measured(const char* pattern, const char* unit, const char* doc, unsigned part, F f) {
  return {pattern, unit, doc, [f, part](const Ctx& c, const Args& a) { return f(c.meas(part), a); }};
}

}  // namespace

std::vector<ObservableSpec> dem_observables() {
  std::vector<ObservableSpec> o = {
      measured("ke", "J",
               "kinetic energy of the free grains (translation + rotation; in a deforming box, of the velocities "
               "relative to the affine flow, as the state holds them)",
               measure_part::kGrains, [](const Measurements& x, const Args&) { return x.ke; }),
      measured("ke_rot", "J", "rotational kinetic energy", measure_part::kGrains,
               [](const Measurements& x, const Args&) { return x.ke_rot; }),
      measured("ke_fluct", "J", "translational kinetic energy per grain, relative to the affine flow",
               measure_part::kGrains, [](const Measurements& x, const Args&) { return x.ke_fluct; }),
      measured("e_contact", "J", "elastic energy stored in the contacts (normal and tangential springs)",
               measure_part::kEnergy, [](const Measurements& x, const Args&) { return x.e_contact; }),
      measured("momentum.{a}", "kg m/s", "total momentum of the free grains, the affine flow included",
               measure_part::kGrains, [](const Measurements& x, const Args& a) { return x.momentum[a.a]; }),
      measured("phi", "", "solid fraction of the grains in the box", measure_part::kGrains,
               [](const Measurements& x, const Args&) { return x.phi; }),
      measured("z", "", "contacts per free grain", measure_part::kContacts,
               [](const Measurements& x, const Args&) { return x.z; }),
      measured("z_star", "", "contacts per free grain that has one", measure_part::kContacts,
               [](const Measurements& x, const Args&) { return x.z_star; }),
      measured("z_mech", "", "contacts per grain of the mechanical skeleton", measure_part::kSkeleton,
               [](const Measurements& x, const Args&) { return x.z_mech; }),
      measured("p0", "", "fraction of free grains with no contact", measure_part::kContacts,
               [](const Measurements& x, const Args&) { return x.p0; }),
      measured("n_contacts", "", "grain-grain and grain-wall contacts", measure_part::kContacts,
               [](const Measurements& x, const Args&) { return static_cast<double>(x.n_contacts); }),
      measured("pressure", "Pa", "trace of the stress / dimension", measure_part::kStress,
               [](const Measurements& x, const Args&) { return x.pressure; }),
      // (nan where it has no value: 0 at stress.yy = 0 read as a measured frictionless state, and
      // entered the means)
      measured("mu", "", "stress ratio |stress.xy| / stress.yy (nan at stress.yy = 0)", measure_part::kStress,
               [](const Measurements& x, const Args&) {
                 return x.stress[1][1] != 0 ? std::abs(x.stress[0][1]) / x.stress[1][1] : kNaN;
               }),
      measured("stress.{a}{b}", "Pa", "grain stress tensor (contact + kinetic), compression positive",
               measure_part::kStress, [](const Measurements& x, const Args& a) { return x.stress[a.a][a.b]; }),
      measured("fabric.{a}{b}", "", "fabric tensor <n n> over grain-grain contacts", measure_part::kContacts,
               [](const Measurements& x, const Args& a) { return x.fabric[a.a][a.b]; }),
      {"n_builds", "", "neighbour-list builds so far",
       [](const Ctx& c, const Args&) { return static_cast<double>(c.s.nbr_builds); }},
      {"n_pairs", "", "listed neighbour pairs",
       [](const Ctx& c, const Args&) { return static_cast<double>(c.s.n_pairs()); }},
      {"kappa", "", "stiffness number at the imposed (else the measured) pressure (nan at a pressure <= 0)",
       [](const Ctx& c, const Args&) {
         const double p = c.m.box_control.on ? c.m.box_control.pressure : c.meas(measure_part::kStress).pressure;
         return p > 0 ? stiffness_number(c.m, p) : kNaN;
       }},
      {"zeta", "", "damping ratio of the lightest pair", [](const Ctx& c, const Args&) { return c.m.zeta_max; }},
      grain_observable("p[{k}].{a}", "m", "position of grain K",
                       [](const Ctx& c, int64_t i, const Args& a) { return c.s.particle_x[c.s.dim * i + a.a]; }),
      grain_observable("p[{k}].v{a}", "m/s", "velocity of grain K (relative to the affine flow)",
                       [](const Ctx& c, int64_t i, const Args& a) { return c.s.particle_v[c.s.dim * i + a.a]; }),
      grain_observable("p[{k}].w{w}", "rad/s", "angular velocity of grain K",
                       [](const Ctx& c, int64_t i, const Args& a) { return c.s.particle_w[c.s.rot * i + a.w]; }),
      grain_observable("p[{k}].f{a}", "N", "total force on grain K, gravity included",
                       [](const Ctx& c, int64_t i, const Args& a) {
                         return c.s.particle_f[c.s.dim * i + a.a] +
                                c.m.weight(c.s.particle_inv_m[i], c.s.particle_frozen[i], a.a);
                       }),
      grain_observable("p[{k}].r", "m", "radius of grain K",
                       [](const Ctx& c, int64_t i, const Args&) { return c.s.particle_r[i]; }),
      grain_observable("p[{k}].m", "kg", "mass of grain K (0 for a frozen grain: it has no finite mass)",
                       [](const Ctx& c, int64_t i, const Args&) {
                         return c.s.particle_frozen[i] ? 0.0 : 1.0 / c.s.particle_inv_m[i];
                       }),
  };
  // pn.K: the fraction of grains with exactly K contacts (Peyneau 2009 Table 3.14).
  ObservableSpec pn = measured(
      "pn.{k}", "", "fraction of free grains with exactly K contacts", measure_part::kContacts,
      [](const Measurements& x, const Args& a) { return a.k < static_cast<int64_t>(x.pn.size()) ? x.pn[a.k] : 0.0; });
  pn.k_count = [](const Model&) { return int64_t{1000}; };
  pn.k_what = "contact count";
  pn.k_listed = 13;
  o.push_back(pn);
  ObservableSpec wall{"wall[{k}].f{a}", "N", "force of the grains on wall K", [](const Ctx& c, const Args& a) {
                        // The grains' force on the wall: minus the wall's force on them.
                        const int nw = c.s.n_walls, D = c.s.dim;
                        double v = 0;
                        for (int64_t i = 0; i < c.s.n; ++i) v -= c.s.wall_f[(i * nw + a.k) * D + a.a];
                        return v;
                      }};
  wall.k_count = [](const Model& m) { return static_cast<int64_t>(m.walls.size()); };
  wall.k_what = "wall";
  wall.k_listed = 1 << 30;
  o.push_back(wall);
  return o;
}

}  // namespace silt::dem
