#include "paste/observables.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "paste/params.hpp"
#include "paste/solve.hpp"
#include "shear/cycle_origin.hpp"
#include "silt/contacts.hpp"

namespace silt::paste {
namespace {

const PasteParams& params(const Model& m) { return m.params.get<PasteParams>(); }

// The imposed pressure: the stresses are relative to it.
double imposed_pressure(const Model& m) { return m.box_control.on ? m.box_control.pressure : 0; }

// The mean of the imposed stresses at the state's time, which the pressure's shares add up to: P,
// or under cycles their mean then (biaxial cycles raise it to P (1 + d (1 - cos wt) / D)).
double imposed_mean_stress(const Model& m, const State& s) {
  if (!m.box_control.on || m.box_control.cycle == StressCycle::kNone) return imposed_pressure(m);
  const CycleOrigin origin = shear::cycle_origin(m, s);
  double sum = 0;
  for (int a = 0; a < m.dim; ++a) sum += m.box_control.stress(a, origin, s.t);
  return sum / m.dim;
}

std::string needs_pressure(const Model& m, const ObservableArgs&) {
  return m.box_control.on ? ""
                          : "it is relative to the imposed pressure (box.pressure), which this scene does not give";
}

std::string needs_sheared(const Model& m, const ObservableArgs&) {
  return m.shear.on ? "" : "it applies to a sheared paste (shear.viscous_number or shear.rate with [lubrication])";
}

// eta_eff divides by the rate: none at an imposed rate of 0 (under an imposed shear stress the rate
// starts at 0 and the first samples have no value, nan in the stats, null in the summary).
std::string needs_rate(const Model& m, const ObservableArgs&) {
  if (std::string why = needs_sheared(m, {}); !why.empty()) return why;
  return m.shear.stress_controlled || m.shear.rate != 0
             ? ""
             : "it divides by the shear rate, which is 0 here (shear.rate): it has no value; leave it out";
}

double solver_stat(const ObservableContext& c, SolverStat k) {
  const auto& v = c.s.module_field(paste_fields().solver);
  return v.size() == kSolverStats ? v[k] : 0.0;
}

// The pressure of a pair force field (the lubrication's, or the implicit contacts' increments),
// split between the pairs in contact and those apart: the thesis counts the lubrication of
// touching grains in the contact pressure (Peyneau 2009 sec. 4.2.3).
std::array<double, 2> pair_pressures(const State& s, FieldId field) {
  const auto& f = s.module_field(field);
  const int D = s.dim;
  std::array<double, 2> p{0, 0};
  if (f.size() != static_cast<size_t>(D * s.n_pairs())) return p;
  double vol = 1;
  for (int a = 0; a < D; ++a) vol *= s.box.len[a];
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t k = s.nbr_start[i]; k < s.nbr_start[i + 1]; ++k) {
      const int32_t j = s.pair_j[k];
      double d[3] = {0, 0, 0}, fd = 0, d2 = 0;
      for (int a = 0; a < D; ++a) d[a] = s.particle_x[D * i + a] - s.particle_x[D * j + a];
      s.box.nearest(d, D);
      for (int a = 0; a < D; ++a) {
        fd += f[D * k + a] * d[a];
        d2 += d[a] * d[a];
      }
      const bool touching = std::sqrt(d2) < s.particle_r[i] + s.particle_r[j];
      p[touching ? 0 : 1] += fd / (D * vol);
    }
  return p;
}

// The hydrodynamic force on grain i along a: the lubrication of its connections (stored at each
// pair as the force on its first grain) and the Stokes drag where lubrication.stokes_drag is on
// (particle_v is relative to the affine flow, which is the liquid's velocity there).
double hydrodynamic_force(const Model& m, const State& s, int64_t i, int a) {
  const auto& f = s.module_field(paste_fields().pair_f_lub);
  const int D = s.dim;
  double h = 0;
  if (f.size() == static_cast<size_t>(D * s.n_pairs()))
    for (int64_t p = 0; p < s.n; ++p)
      for (int32_t k = s.nbr_start[p]; k < s.nbr_start[p + 1]; ++k) {
        if (p == i) h += f[D * k + a];
        else if (s.pair_j[k] == i) h -= f[D * k + a];
      }
  const PasteParams& pp = params(m);
  if (pp.stokes_drag) h -= 6 * std::numbers::pi * pp.eta * s.particle_r[i] * s.particle_v[D * i + a];
  return h;
}

double trace(const std::array<std::array<double, 3>, 3>& t, int d) {
  double x = 0;
  for (int a = 0; a < d; ++a) x += t[a][a];
  return x / d;
}

}  // namespace

double friction_mobilisation(const State& s) {
  double sum = 0;
  int64_t count = 0;
  for_each_contact(s, [&](const Contact& c) {
    if (!(c.fn > 0)) return;
    double ft2 = 0;
    for (int a = 0; a < s.dim; ++a) {
      const double t = c.f[a] - c.fn * c.d[a] / c.dist;
      ft2 += t * t;
    }
    sum += std::sqrt(ft2) / c.fn;
    ++count;
  });
  return count ? sum / static_cast<double>(count) : 0.0;
}

std::vector<ObservableSpec> paste_observables() {
  using C = const ObservableContext&;
  using A = const ObservableArgs&;
  std::vector<ObservableSpec> o = {
      // (at a fixed volume over the measured sigma_yy, as I is: INTERFACE.md gives Vi where a rate is
      // imposed, and it was refused there)
      {"Vi", "",
       "viscous number eta gammadot / P (Peyneau 2009 eq. 1.34; eta gammadot a / P in 2D) at the imposed (else "
       "the measured sigma_yy) pressure (nan at a pressure <= 0)",
       [](C c, A) {
         const double p = c.m.box_control.on ? imposed_pressure(c.m) : c.meas(measure_part::kStress).stress[1][1];
         return p > 0 ? viscous_number(c.m, params(c.m).eta, c.s.shear_rate, p)
                      : std::numeric_limits<double>::quiet_NaN();
       }},
      {"mobilisation", "", "friction mobilisation <|F_T| / F_N> over the contacts",
       [](C c, A) { return friction_mobilisation(c.s); }},
      {"p_cont_ratio", "",
       "pressure carried by the contacts / P (under cycles, / the imposed stresses' mean then): their elastic "
       "and frictional forces and the lubrication between touching grains (Peyneau 2009 sec. 4.2.3)",
       [](C c, A) {
         const Measurements& x = c.meas(measure_part::kStress);
         // (the pressure less that of the pair fields: the contacts' own forces and the kinetic part)
         const double elastic = x.pressure - trace(x.stress_pairs, c.m.dim);
         const auto implicit = pair_pressures(c.s, paste_fields().pair_f_implicit);
         return (elastic + pair_pressures(c.s, paste_fields().pair_f_lub)[0] + implicit[0] + implicit[1]) /
                imposed_mean_stress(c.m, c.s);
       }},
      {"p_lub_ratio", "",
       "pressure carried by the lubrication between grains apart / P, as p_cont_ratio (p_cont_ratio + p_lub_ratio "
       "= 1 when every axis's stress is imposed at P; the measured pressure / P otherwise)",
       [](C c, A) { return pair_pressures(c.s, paste_fields().pair_f_lub)[1] / imposed_mean_stress(c.m, c.s); }},
      {"eta_eff", "",
       "effective viscosity |stress.xy| / (eta gammadot), in units of eta (|stress.xy| / (eta gammadot a) in 2D): "
       "mu / Vi, the grains' part (their contacts and lubrication; the liquid's own eta gammadot between them is "
       "not in the model, so a dilute paste reads near 0, not 1)",
       [](C c, A) {
         // (at fixed volume too: it needs a rate, not a pressure; none at a rate of 0)
         const double scale = viscous_stress(c.m, params(c.m).eta, c.s.shear_rate);
         return scale > 0 ? std::abs(c.meas(measure_part::kStress).stress[0][1]) / scale
                          : std::numeric_limits<double>::quiet_NaN();
       }},
      {"solver.iters", "", "iterations of the last lubrication solve (0 for a direct solve)",
       [](C c, A) { return solver_stat(c, kLastIterations); }},
      {"solver.residual", "", "relative residual |F - Xi V| / |F| of the last lubrication solve",
       [](C c, A) { return solver_stat(c, kLastResidual); }},
      {"solver.stress_error", "",
       "estimated error of the grains' stress after the last lubrication solve, relative to it "
       "(lubrication.stress_tolerance; nan where none is estimated: the check off, a direct solve)",
       [](C c, A) { return stress_error_of(solver_stat(c, kStressError)); }},
      {"solver.refactorisations", "", "Cholesky factorisations of Xi so far",
       [](C c, A) { return solver_stat(c, kRefactorizations); }},
      {"solver.iters_mean", "", "mean iterations per lubrication solve so far",
       [](C c, A) {
         const double n = solver_stat(c, kSolves);
         return n > 0 ? solver_stat(c, kIterationsTotal) / n : 0.0;
       }},
      {"solver.coarse", "",
       "stiff directions the last lubrication solve corrected its factor on (lubrication.coarse_ratio)",
       [](C c, A) { return solver_stat(c, kCoarseColumns); }},
      {"connections", "", "lubricated connections (gaps below h_max) of the last solve",
       [](C c, A) { return solver_stat(c, kConnections); }},
      grain_observable("p[{k}].h{a}", "N",
                       "hydrodynamic force on grain K: the lubrication of its connections (and its Stokes drag "
                       "where lubrication.stokes_drag is on)",
                       [](C c, int64_t i, A a) { return hydrodynamic_force(c.m, c.s, i, a.a); }),
  };
  o[0].check = needs_sheared;
  o[2].check = needs_pressure;
  o[3].check = needs_pressure;
  o[4].check = needs_rate;  // eta_eff: a rate, at an imposed pressure or a fixed volume
  return o;
}

}  // namespace silt::paste
