// The drag module: a scene with [drag] puts a Stokes drag on every grain (drag/drag.hpp). It adds
// one key, two fields (the force and torque it adds to the grains' motion) and one observable.
#include <algorithm>
#include <numbers>
#include <sstream>

#include "drag/drag.hpp"
#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt::drag {
namespace {

// The shortest Stokes time of a free grain, m / (6 pi eta r).
double shortest_stokes_time(const Model& m, double eta) {
  double tau = 1e308;
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i]) tau = std::min(tau, m.init.mass[i] / translational_coefficient(eta, m.init.radius[i]));
  return tau;
}

void compile_drag(const SceneDesc& d, Model& m) { m.params.get<DragParams>().viscosity = d.real("drag.viscosity"); }

// Once the time step is known: the explicit drag decays monotonically only for dt < tau.
void finish_drag(const SceneDesc& d, Model& m) {
  const double eta = m.params.get<DragParams>().viscosity;
  const double tau = shortest_stokes_time(m, eta);
  if (m.dt > tau)
    d.fail("drag.viscosity", "the lightest grain's Stokes time m / (6 pi eta r) = " + format_number(tau, 4) +
                                 " s is shorter than the time step " + format_number(m.dt, 4) +
                                 " s: the explicit drag would oscillate; reduce drag.viscosity or run.dt");
}

std::string describe_drag(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  const double eta = m.params.get<DragParams>().viscosity;
  o << "drag         Stokes drag 6 pi eta r v, eta = " << eta << " Pa s; shortest Stokes time "
    << shortest_stokes_time(m, eta) << " s (dt / tau = " << m.dt / shortest_stokes_time(m, eta) << ")\n";
  return o.str();
}

}  // namespace

const ModuleSpec& module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "drag";
    s.doc = "Stokes drag on every grain (a still viscous liquid)";
    s.keys = {
        {"drag.viscosity",
         KeyType::kReal,
         std::nullopt,
         Range::positive(),
         "Pa s",
         true,
         {},
         "Viscosity of the liquid around the grains: Stokes drag 6 pi eta r v and torque 8 pi eta r^3 omega on each."}};
    s.fields = {{"particle_f_drag", Extent::kGrainVec, "N", "Stokes drag force on the grain; drag_forces"},
                {"particle_t_drag", Extent::kGrainRot, "N m", "Stokes drag torque on the grain; drag_forces"}};
    ObservableSpec power{"drag.power", "W", "power the drag takes from the grains (negative)",
                         [](const ObservableContext& c, const ObservableArgs&) {
                           const auto f = double_field(c.s, find_field("particle_f_drag")->id);
                           const auto t = double_field(c.s, find_field("particle_t_drag")->id);
                           double p = 0;
                           for (size_t k = 0; k < f.size(); ++k) p += f[k] * c.s.particle_v[k];
                           for (size_t k = 0; k < t.size(); ++k) p += t[k] * c.s.particle_w[k];
                           return p;
                         }};
    // (p[K].hA is the paste's too: the words for a scene with neither, where this one is met first.)
    ObservableSpec hydro = grain_observable("p[{k}].h{a}", "N", "hydrodynamic force on grain K: its Stokes drag",
                                            [](const ObservableContext& c, int64_t i, const ObservableArgs& a) {
                                              const auto f = double_field(c.s, find_field("particle_f_drag")->id);
                                              return f.empty() ? 0.0 : f[c.s.dim * i + a.a];
                                            });
    hydro.check = [](const Model& m, const ObservableArgs&) -> std::string {
      if (m.module_on("drag") || m.module_on("paste")) return "";
      return "the hydrodynamic force p[K].hA applies where a liquid acts on the grains ([drag] or [lubrication])";
    };
    s.observables = {power, hydro};
    s.enabled = [](const SceneDesc& d) { return d.has("drag.viscosity"); };
    s.needs_grains = true;
    s.compile = compile_drag;
    s.finish = finish_drag;
    s.describe = describe_drag;
    return s;
  }();
  return spec;
}

}  // namespace silt::drag
