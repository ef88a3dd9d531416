// Speed against accuracy for the DEM's numerical knobs.
//
//   build/bench/dem_knobs [--settled FILE] [--steps N]
//
// 1. Time step: restitution and contact duration of the binary collision of
//    scenes/collision_normal.toml (Izard's linear law, e = 0.5 and 0.9) against the closed form, for dt = t_c/10 ...
//    t_c/400; cost = steps per contact. Velocity Verlet with the dashpot on half-step velocities is first order in dt
//    for e.
// 2. Verlet skin: cost of the chute (17,600 grains, settled state) for skins of 0.025 to 0.3
//    diameters; the skin changes no result, only how often lists are rebuilt and how many pairs
//    are tested per step.
// 3. Contact skin: cost of the same run when only listed pairs closer than a gap of 0 to 0.4
//    skins are tested each step (contact candidates, re-selected when grains have moved half of
//    that gap); the state after the run must be the same, bit for bit, as testing every pair.
// Appends to bench/results/dem_knobs.csv.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "core/workspace.hpp"
#include "dem/workspace.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

// `steps` steps as `silt run` does them (Simulation::run: the pair forces are stored only where
// seen, here at the end).
void run_steps(Simulation& sim, int64_t steps) {
  RunOptions opt;
  opt.steps = steps;
  if (sim.run(opt).end != RunEnd::kDone) {
    std::fprintf(stderr, "silt failed: %s\n", sim.state().failure.message.c_str());
    std::exit(3);
  }
}

std::string csv_path() { return std::string(SILT_SOURCE_DIR) + "/bench/results/dem_knobs.csv"; }
const char* kHeader = "date,knob,value,case,error_or_rate,aux1,aux2";

void time_step_table() {
  std::printf("1. time step: binary collision, spring_dashpot, t_c = 1e-4 s\n");
  std::printf("%-8s %-10s %-14s %-14s %-14s\n", "e", "t_c/dt", "e measured", "rel. error", "duration/t_c");
  for (double e : {0.5, 0.9}) {
    for (double per : {10.0, 20.0, 50.0, 100.0, 200.0, 400.0}) {
      // scenes/collision_normal.toml: two acetate spheres meeting at 1 m/s.
      std::ostringstream re, dt;
      re << "contact.restitution=" << e;
      dt << "run.dt_over_tc=" << 1.0 / per;
      Simulation sim(compile(load_scene_file(std::string(SILT_SOURCE_DIR) + "/scenes/collision_normal.toml",
                                             {parse_override(re.str()), parse_override(dt.str())})),
                     1);
      int64_t touching = 0;
      bool started = false;
      while (sim.step()) {
        const State& s = sim.state();
        const double d = std::abs(s.particle_x[3] - s.particle_x[0]);
        if (d < s.particle_r[0] + s.particle_r[1]) {
          started = true;
          ++touching;
        } else if (started) {
          break;
        }
      }
      const State& s = sim.state();
      const double em = (s.particle_v[3] - s.particle_v[0]) / 1.0;
      const double dur = touching * s.dt / 1e-4;
      std::printf("%-8.2f %-10.0f %-14.6f %-14.3e %-14.4f\n", e, per, em, std::abs(em - e) / e, dur);
      std::ostringstream row;
      row << bench::today() << ",dt_over_tc," << 1.0 / per << ",restitution_e" << e << "," << std::abs(em - e) / e
          << "," << dur << "," << per;
      bench::append_csv(csv_path(), kHeader, row.str());
    }
  }
}

const std::string& chute_scene() {
  static const std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/chute.toml";
  return scene;
}

State settled_chute(const std::string& settled_file) {
  const Model base = compile(load_scene_file(chute_scene()));
  if (!settled_file.empty() && std::ifstream(settled_file).good()) return read_checkpoint(settled_file, base);
  std::printf("   (settling the chute for 30,000 steps first)\n");
  Simulation sim(base, 2);
  for (int k = 0; k < 30000; ++k) sim.step();
  if (!settled_file.empty()) write_checkpoint(settled_file, base, sim.state());
  return sim.state();
}

void skin_table(const State& settled, int64_t steps) {
  const std::string& scene = chute_scene();
  std::printf("\n2. Verlet skin: chute, %lld steps from the settled state, 1 thread\n", static_cast<long long>(steps));
  std::printf("%-10s %-16s %-10s %-14s %-12s %-12s\n", "skin/d", "particle-steps/s", "builds", "pairs/grain",
              "bytes/grain", "KE at end");
  for (double skin : {0.025, 0.05, 0.1, 0.2, 0.3}) {
    std::ostringstream o;
    o << "neighbor.skin=" << skin * 0.98;
    Model m = compile(load_scene_file(scene, {parse_override(o.str())}));
    Simulation sim(std::move(m), 1);
    State st = settled;
    st.nbr_valid = false;  // lists of this skin
    sim.restore(st);
    const int64_t b0 = sim.state().nbr_builds;
    const double t0 = bench::now_s();
    run_steps(sim, steps);
    const double rate = sim.state().n * static_cast<double>(steps) / (bench::now_s() - t0);
    const Measurements meas = measure(sim.model(), sim.state());
    std::printf("%-10.3f %-16.4g %-10lld %-14.2f %-12.0f %-12.1f\n", skin, rate,
                static_cast<long long>(sim.state().nbr_builds - b0),
                static_cast<double>(sim.state().n_pairs()) / sim.state().n,
                static_cast<double>(state_bytes(sim.state())) / sim.state().n, meas.ke);
    std::ostringstream row;
    row << bench::today() << ",skin_over_d," << skin << ",chute_1thread," << rate << "," << sim.state().nbr_builds - b0
        << "," << static_cast<double>(sim.state().n_pairs()) / sim.state().n;
    bench::append_csv(csv_path(), kHeader, row.str());
  }
}

// Runs `steps` steps of the chute from `settled` with neighbor.contact_skin = fraction * skin on one
// thread; returns particle-steps per second, and the state hash and selections through the
// pointers.
double contact_skin_run(const State& settled, int64_t steps, double skin, double fraction, uint64_t* hash,
                        int64_t* selections, double* per_grain) {
  std::ostringstream o;
  o << "neighbor.contact_skin=" << fraction * skin;
  Simulation sim(compile(load_scene_file(chute_scene(), {parse_override(o.str())})), 1);
  sim.restore(settled);
  sim.step();  // lists and candidates of this run, outside the timing
  const dem::DemWorkspace& w = sim.workspaces().get<dem::DemWorkspace>();
  const int64_t sel0 = w.cand_selections;
  const double t0 = bench::now_s();
  run_steps(sim, steps - 1);
  const double rate = sim.state().n * static_cast<double>(steps - 1) / (bench::now_s() - t0);
  const State& s = sim.state();
  *hash = state_hash(s);
  *selections = w.cand_selections - sel0;
  *per_grain = static_cast<double>(w.n_candidates(s.nbr_start)) / s.n;
  return rate;
}

void contact_skin_table(const State& settled, int64_t steps) {
  const std::vector<double> fractions = {0.0, 0.025, 0.05, 0.1, 0.2, 0.4};
  const int repeats = 5;  // interleaved, best of: the machine's speed drifts over minutes
  std::vector<double> best(fractions.size(), 0.0), per_grain(fractions.size());
  std::vector<uint64_t> hash(fractions.size());
  std::vector<int64_t> sel(fractions.size());
  const double skin = compile(load_scene_file(chute_scene())).skin;
  for (int r = 0; r < repeats; ++r)
    for (size_t k = 0; k < fractions.size(); ++k)
      best[k] =
          std::max(best[k], contact_skin_run(settled, steps, skin, fractions[k], &hash[k], &sel[k], &per_grain[k]));
  std::printf("\n3. contact skin: chute, %lld steps from the settled state, 1 thread, best of %d\n",
              static_cast<long long>(steps), repeats);
  std::printf("%-16s %-16s %-12s %-18s %-10s\n", "contact/skin", "particle-steps/s", "selections", "candidates/grain",
              "same bits");
  for (size_t k = 0; k < fractions.size(); ++k) {
    const bool same = hash[k] == hash[0];
    std::printf("%-16s %-16.4g %-12lld %-18.2f %-10s\n",
                k == 0 ? "0 (all pairs)" : std::to_string(fractions[k]).c_str(), best[k],
                static_cast<long long>(sel[k]), per_grain[k], same ? "yes" : "NO");
    std::ostringstream row;
    row << bench::today() << ",contact_skin_over_skin," << fractions[k] << ",chute_1thread," << best[k] << "," << sel[k]
        << "," << (same ? 1 : 0);
    bench::append_csv(csv_path(), kHeader, row.str());
  }
}

int run(int argc, char** argv) {
  std::string settled;
  int64_t steps = 2000;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--settled")) settled = argv[i + 1];
    else if (!std::strcmp(argv[i], "--steps")) steps = std::atoll(argv[i + 1]);
  }
  time_step_table();
  const State chute = settled_chute(settled);
  skin_table(chute, steps);
  contact_skin_table(chute, steps);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
