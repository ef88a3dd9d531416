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

// The shortest Stokes time of a free grain: of its translation, m / (6 pi eta r), or of its
// rotation, I / (8 pi eta r^3), 0.3 of it for a sphere (the translation's alone was checked: a
// spinning ball at 0.3 to 1 times it passed `silt check`, and its spin flipped sign every step
// until the energy check failed, advising a shorter run.dt).
struct StokesTime {
  double tau = 1e308;
  bool rotation = false;
};

StokesTime shortest_stokes_time(const Model& m, double eta) {
  StokesTime out;
  for (int64_t i = 0; i < m.n_grains; ++i) {
    if (m.init.frozen[i]) continue;
    const double r = m.init.radius[i];
    const double moved = m.init.mass[i] / translational_coefficient(eta, r);
    const double turned = m.init.inertia[i] / rotational_coefficient(eta, r);
    if (moved < out.tau) out = {moved, false};
    if (turned < out.tau) out = {turned, true};
  }
  return out;
}

void compile_drag(const SceneDesc& d, Model& m) { m.params.get<DragParams>().viscosity = d.real("drag.viscosity"); }

// Once the time step is known: the explicit drag decays monotonically only for dt < tau.
void finish_drag(const SceneDesc& d, Model& m) {
  const double eta = m.params.get<DragParams>().viscosity;
  const StokesTime t = shortest_stokes_time(m, eta);
  if (m.dt > t.tau)
    d.fail("drag.viscosity", std::string("the lightest grain's Stokes time ") +
                                 (t.rotation ? "of rotation I / (8 pi eta r^3)" : "m / (6 pi eta r)") + " = " +
                                 format_number(t.tau, 4) + m.unit("s") + " is shorter than the time step " +
                                 format_number(m.dt, 4) + m.unit("s") +
                                 ": the explicit drag would oscillate; reduce drag.viscosity or the time step (" +
                                 d.first_given({"run.dt", "run.dt_over_tc"}, "run.dt_over_tc") + ")");
}

std::string describe_drag(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  const double eta = m.params.get<DragParams>().viscosity;
  const StokesTime t = shortest_stokes_time(m, eta);
  o << "drag         Stokes drag 6 pi eta r v, eta = " << eta << m.unit("Pa s") << "; shortest Stokes time " << t.tau
    << m.unit("s") << (t.rotation ? " (of rotation)" : "") << " (dt / tau = " << m.dt / t.tau << ")\n";
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
    s.force_parameters = [](const Model& m) { return std::vector<double>{m.params.get<DragParams>().viscosity}; };
    return s;
  }();
  return spec;
}

}  // namespace silt::drag
