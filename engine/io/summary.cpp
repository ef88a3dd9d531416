#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "silt/io.hpp"
#include "silt/module.hpp"

namespace silt {

void write_summary(const std::string& path, const SummaryInput& in, const Simulation& sim, const StatsWriter& stats) {
  using nlohmann::json;
  const Model& m = sim.model();
  const State& now = sim.state();
  const State& s = in.kept ? *in.kept : now;
  json j;
  j["scene"] = in.scene;
  j["status"] = in.status;
  j["exit_code"] = in.exit_code;
  j["steps"] = s.step;
  j["steps_run"] = in.steps_run;
  j["sim_time"] = s.t;
  j["wall_s"] = in.wall_s;
  j["threads"] = sim.threads();
  j["n_particles"] = m.n_grains;
  j["n_frozen"] = m.n_frozen;
  j["dimension"] = m.dim;
  j["dt"] = s.dt;
  j["particle_steps_per_s"] = in.wall_s > 0 ? static_cast<double>(m.n_grains) * in.steps_run / in.wall_s : 0.0;
  if (m.cells[0] > 0) {
    const int64_t n_cells = m.n_cells();
    const auto cells = static_cast<double>(n_cells);
    j["cells"] = n_cells;
    j["fluid_cell_steps_per_s"] = in.wall_s > 0 ? cells * static_cast<double>(in.steps_run) / in.wall_s : 0.0;
  }
  j["neighbor_builds"] = s.nbr_builds;
  j["memory_bytes"] = state_bytes(s);
  json stages = json::object();
  for (const auto& [name, st] : now.profile) stages[name] = st.seconds();
  j["stages"] = stages;
  if (const PreparationReport* p = in.preparation) {
    json prep_stages = json::object();
    for (const auto& [name, st] : p->profile) prep_stages[name] = st.seconds();
    j["preparation"] = {{"steps", p->steps}, {"wall_s", p->wall_s}, {"stages", prep_stages}};
  }
  for (const Module& mod : modules())
    if (mod.spec->summary && m.module_on(mod.spec->name)) {
      json g = json::object();
      // Counts (solves, iterations, factorisations) as the integers they are.
      const auto& counts = mod.spec->summary_counts;
      for (const auto& [key, value] : mod.spec->summary(m, s))
        g[key] = std::find(counts.begin(), counts.end(), key) != counts.end() && std::abs(value) < 9e15
                     ? json(static_cast<int64_t>(value))
                     : json(value);
      j[mod.spec->summary_group] = g;
    }
  json obs = json::object();
  const auto& names = stats.names();
  j["average_from"] = in.average_from;
  std::vector<std::string> warnings = in.warnings;
  for (size_t k = 0; k < names.size(); ++k) {
    const BlockAverage b = stats.average(k, in.average_from);
    // (one undefined sample, mu where stress.yy is 0 at t = 0, made the mean null without a word)
    if (b.nans > 0 && b.nans < b.n)
      warnings.push_back(names[k] + ": " + std::to_string(b.nans) + " of its " + std::to_string(b.n) + " samples " +
                         (b.nans == 1 ? "is" : "are") +
                         " nan (undefined there), so its mean and error are null; --average-from a time past them "
                         "averages the others");
    json o;
    o["mean"] = b.n ? json(b.mean) : json(nullptr);
    o["err"] = b.n > 1 ? json(b.err) : json(nullptr);
    o["last"] = stats.last_row().size() > k ? json(stats.last_row()[k]) : json(nullptr);
    o["n"] = b.n;
    o["block"] = b.block;
    o["converged"] = b.converged;
    obs[names[k]] = o;
  }
  j["observables"] = obs;
  if (!in.profiles.empty()) {
    json profiles = json::object();
    for (const ProfileSeries& p : in.profiles) {
      json o, mean = json::array(), err = json::array();
      for (size_t k = 0; k < p.x.size(); ++k) {
        const BlockAverage b = k < p.bins.size() ? p.bins[k].result() : BlockAverage{};
        mean.push_back(b.n ? json(b.mean) : json(nullptr));
        err.push_back(b.n > 1 ? json(b.err) : json(nullptr));
      }
      o["coordinate"] = p.coordinate;
      o["x"] = p.x;
      o["mean"] = mean;
      o["err"] = err;
      o["n"] = p.samples;
      profiles[p.name] = o;
    }
    j["profiles"] = profiles;
  }
  if (const std::vector<LineSample> lines = module_lines(m, s); !lines.empty()) {
    json out = json::object();
    for (const LineSample& l : lines) {
      json o, x = json::array();
      for (const auto& p : l.x) x.push_back(std::vector<double>(p.begin(), p.begin() + m.dim));
      o["field"] = l.field;
      o["s"] = l.s;
      o["x"] = x;
      o["value"] = l.value;
      out[l.name] = o;
    }
    j["lines"] = out;
  }
  const StepFailure& failure = in.failure.failed ? in.failure : now.failure;
  if (failure.failed) {
    json f;
    f["step"] = failure.step;
    f["stage"] = failure.stage;
    f["particle"] = failure.particle;
    f["parameter"] = failure.parameter;
    f["message"] = failure.message;
    if (in.failure.failed) f["during"] = "preparation";
    j["failure"] = f;
  }
  j["warnings"] = warnings;
  write_text_file(path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n", "summary");
}

}  // namespace silt
