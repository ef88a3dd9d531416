// Procedure O of Peyneau (2009) sec. 3.1.2: the initial grains are compressed isotropically at
// the imposed pressure (every periodic length controlled by eq. 3.11, no shear) until they form
// a static packing; the scene's run then starts from it.
#include <algorithm>

#include "shear/stages.hpp"
#include "silt/module.hpp"
#include "silt/observables.hpp"
#include "silt/simulation.hpp"

namespace silt {

Model compression_model(const Model& m) {
  Model c = m;
  for (const Module& mod : modules())
    if (mod.spec->prepare_dry && m.module_on(mod.spec->name)) mod.spec->prepare_dry(c);
  c.shear = ShearControl{};
  c.box.lees_edwards = false;
  c.box.le_offset = 0;
  c.box_control.on = true;
  c.box_control.pressure = preparation_pressure(m);
  c.box_control.cycle = StressCycle::kNone;
  for (int k = 0; k < c.dim; ++k) c.box_control.controlled[k] = c.box.periodic[k];
  c.until_static.on = true;
  c.prepare = Preparation{};
  return c;
}

State adopt_state(const Model& m, State s) {
  s.cells = m.cells;  // a grid's fields of another size are made anew below
  if (s.box.lees_edwards != m.box.lees_edwards) {
    s.box.lees_edwards = m.box.lees_edwards;
    s.box.le_offset = 0;
    s.le_displacement = 0;
    s.nbr_valid = false;  // the cell stencil depends on the boundary conditions
  }
  if (!m.shear.on) s.shear_rate = 0;
  else shear::impose_shear_rate(m, s);
  for (int k = 0; k < 3; ++k)
    if (!m.box_control.on || !m.box_control.controlled[k]) s.box_rate[k] = 0;
  // The fields of modules the state was made without (a dry compression before a paste).
  fit_module_fields(m, s, FitFields::kMismatched);
  return s;
}

namespace {

FieldId compression_field() {
  static const FieldId id = find_field("dem_compression")->id;
  return id;
}

}  // namespace

bool in_compression(const State& s) {
  const std::vector<double>& mark = s.module_field(compression_field());
  return !mark.empty() && mark[0] != 0;
}

State prepare_packing(const Model& m, int threads, PreparationReport* report, const std::atomic<bool>* interrupt,
                      const State* from) {
  const Model c = compression_model(m);
  Simulation sim(c, threads);
  // A compression's state before its end goes on from its step (the scene's run started from a
  // half-compressed packing: a restored last good state of a failed compression was run as it was).
  int64_t done = 0;
  if (from) {
    State s = *from;
    s.module_field(compression_field()).clear();
    done = std::min(s.step, m.prepare.max_steps);
    sim.restore(adopt_state(c, std::move(s)));
  }
  const int64_t budget = m.prepare.max_steps - done;
  RunOptions opt;
  opt.steps = budget;
  opt.stop_when_static = true;
  opt.interrupt = interrupt;
  RunReport rep;
  bool reached = false;
  if (m.prepare.phi > 0) {
    // In chunks, until the solid fraction is reached (or equilibrium first). A chunk ends short of
    // the target at the last one's rate, so that the chunks shorten to single steps as it nears:
    // the overshoot is one step's compaction (chunks of limits.check_every steps took 200 spheres
    // from below 0.45 to 0.564).
    int64_t chunk_steps = c.limits.check_every;
    double phi = measure(c, sim.state(), measure_part::kGrains).phi;
    while (rep.steps_done < budget) {
      opt.steps = std::min(chunk_steps, budget - rep.steps_done);
      const RunReport chunk = sim.run(opt);
      rep.steps_done += chunk.steps_done;
      rep.wall_s += chunk.wall_s;
      rep.end = chunk.end;
      if (chunk.end != RunEnd::kDone) break;
      const double now = measure(c, sim.state(), measure_part::kGrains).phi;
      if (now >= m.prepare.phi) {
        reached = true;
        break;
      }
      const double per_step = chunk.steps_done > 0 ? (now - phi) / static_cast<double>(chunk.steps_done) : 0.0;
      if (per_step > 0)
        chunk_steps =
            std::clamp<int64_t>(static_cast<int64_t>(0.5 * (m.prepare.phi - now) / per_step), 1, c.limits.check_every);
      phi = now;
    }
  } else {
    rep = sim.run(opt);
  }
  if (report) {
    report->steps = done + rep.steps_done;
    report->wall_s = rep.wall_s;
    report->end = rep.end;
    report->reached_phi = reached;
    report->failure = sim.state().failure.message;
    report->profile = sim.state().profile;
    if (rep.end == RunEnd::kFailed) {
      report->failure_detail = sim.state().failure;
      report->last_good = sim.last_good_state();
      if (report->last_good) report->last_good->module_field(compression_field()) = {1.0};
    }
    report->phi = measure(c, sim.state(), measure_part::kGrains).phi;
  }
  State s = sim.state();
  s.t = 0;
  s.step = 0;
  s.profile = Profile{};  // (the run's stage times are the run's: the summary's stages held the compression's)
  for (auto& v : s.particle_v) v = 0;
  for (auto& w : s.particle_w) w = 0;
  s.shear_strain = 0;
  if (m.prepare.dilation != 1) {
    const double f = m.prepare.dilation;
    for (int64_t i = 0; i < s.n; ++i)
      for (int k = 0; k < s.dim; ++k)
        if (s.box.periodic[k])
          s.particle_x[s.dim * i + k] = s.box.lo[k] + f * (s.particle_x[s.dim * i + k] - s.box.lo[k]);
    for (int k = 0; k < s.dim; ++k)
      if (s.box.periodic[k]) s.box.len[k] *= f;
    for (auto& h : s.pair_hist) h = 0;
    // (and the forces, of the configuration before: a paste whose first solve failed sampled this
    // state with the compression's stress, 0.91 P, and no contact)
    for (std::vector<double>* field : {&s.pair_f, &s.particle_f, &s.particle_t})
      std::fill(field->begin(), field->end(), 0.0);
    s.nbr_valid = false;
  }
  return adopt_state(m, std::move(s));
}

}  // namespace silt
