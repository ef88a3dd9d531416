// compile(SceneDesc) -> Model: each enabled module compiles its part, in module order; then the
// time step and the run length; then each module finishes (what needs every module and the time
// step: the energy scale, the observables, the initial overlaps).
#include <algorithm>
#include <cmath>

#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt {
namespace {

// The time step, and the run length in steps. The contact time comes from the DEM's part of
// compile(), the step the modules propose from theirs; each module checks the step against its
// own limits when it finishes.
void setup_time(const SceneDesc& d, Model& m) {
  const bool abs = d.has("run.dt"), rel = d.has("run.dt_over_tc");
  m.dt = abs ? d.real("run.dt") : (rel ? d.real("run.dt_over_tc") * m.t_contact : m.default_dt);
  // (the key a failure and the shell's notes name: the step a stiffer contact shortened comes
  // from run.dt_over_tc, not from a run.dt the scene does not give)
  if (rel && m.dt_key == "run.dt") m.dt_key = "run.dt_over_tc";
  if (!(m.dt > 0) || !std::isfinite(m.dt))
    d.fail(abs ? "run.dt" : "run.dt_over_tc",
           "the time step is " + format_number(m.dt) + " s: it must be finite and positive");
  if (d.has("run.steps")) m.run_steps = d.integer("run.steps");
  if (d.has("run.time")) {
    m.run_time = d.real("run.time");
    m.run_steps = steps_in(d.real("run.time"), m.dt);
    // A module's step (a fluid's from its CFL number and velocity scale) names its key: the cause
    // may be there (a lid of 1e300 m/s), not in the run's length.
    if (m.run_steps < 0)
      d.fail("run.time",
             "run.time is " + too_many_steps(m.dt) +
                 (m.dt_key.rfind("run.", 0) != 0 ? " (the step set by " + m.dt_key + " and the scene's speeds)" : ""));
  }
  m.until_static.on = d.boolean("run.stop_when_static");
  m.until_static.force_tol = d.real("run.static_force_tol");
  m.until_static.stress_tol = d.real("run.static_stress_tol");
  m.until_static.ke_tol = d.real("run.static_ke_tol");
}

}  // namespace

int64_t steps_in(double time, double dt) {
  const double n = std::ceil(time / dt - 1e-9);
  if (!(n <= static_cast<double>(kMaxRunSteps))) return -1;
  return std::max<int64_t>(0, static_cast<int64_t>(n));
}

std::string too_many_steps(double dt) {
  return "too long, more than " + std::string(kMaxRunStepsText) + " steps of " + format_number(dt) + " s";
}

std::vector<std::pair<std::string, std::string>> Model::files_read() const {
  std::vector<std::pair<std::string, std::string>> out{{scene_file, "the scene file"}};
  for (const std::string& c : checkpoints_read) out.emplace_back(c, "a checkpoint the scene reads (frozen_from)");
  return out;
}

bool Model::module_on(std::string_view name) const {
  return name == "core" || std::find(modules.begin(), modules.end(), name) != modules.end();
}

namespace {

// A module that acts on grains, turned on in a scene without them (a resolved fluid alone, the
// dem module off): refused at the first of its tables the scene gives (at a key of it, or at its
// header when it is empty). Its stages would have been wired to the grains' absent ones.
void check_needs_grains(const SceneDesc& d, const Model& m, const ModuleSpec& s) {
  if (!s.needs_grains || m.module_on("dem")) return;
  for (const KeySpec& k : s.keys) {
    const std::string table = k.path.substr(0, k.path.find('.')), prefix = table + ".";
    if (!d.has_table(table)) continue;
    const auto it = d.entries.lower_bound(prefix);
    d.fail(it != d.entries.end() && it->first.starts_with(prefix) ? it->first : prefix,
           "[" + table +
               "] acts on grains, and this scene has none (a resolved fluid alone: grains are not coupled "
               "to it yet); remove [" +
               table + "]");
  }
}

}  // namespace

Model compile(const SceneDesc& d) {
  Model m;
  m.desc = d;
  const SceneDesc& D = m.desc;  // read through the copy so that its use marks are the ones checked
  D.check_rules();
  for (const Module& mod : modules())
    if (!mod.spec->enabled || mod.spec->enabled(D)) m.modules.push_back(mod.spec->name);
  for (const Module& mod : modules())
    if (m.module_on(mod.spec->name)) check_needs_grains(D, m, *mod.spec);
  for (const Module& mod : modules())
    if (mod.spec->compile && m.module_on(mod.spec->name)) mod.spec->compile(D, m);
  setup_time(D, m);
  for (const Module& mod : modules())
    if (mod.spec->finish && m.module_on(mod.spec->name)) mod.spec->finish(D, m);
  D.check_all_used();
  return m;
}

}  // namespace silt
