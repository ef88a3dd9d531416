// Lubricated granular pastes (Peyneau 2009 ch. 2 and 4; scenes/paste_iso.toml and
// paste_shear.toml): validation against the thesis and the cost of the implicit solve.
//
//   build/bench/paste [--threads N] [--only SECTION] [--quick] [--seeds N] [--set KEY=VALUE ...]
//
// Sections:
//   iso          Table 2.3: isotropic equilibrium at h_min/a = 1e-3 and 1e-5, linear and constant
//                cutoff, --seeds samples (default 5): Phi, z*, M, T P/eta, next to the thesis
//                and the dry bounds 0.802 / 0.836.
//   equilibrium  Table 2.2: time to equilibrium T P/eta against h_min/a from 1e-2 to 1e-8 (one
//                packing), with the wall time, steps and solver iterations; each run stops after
//                --budget seconds of wall time (default 600, the target for 1e-8) if not static.
//   knobs        dt_change (the adaptive step's threshold) and the solver (direct, factor_pcg
//                at three refactorisation thresholds and refactorised every 10 or 100 solves, cg)
//                at h_min/a = 1e-3: cost against the equilibrium reached.
//   shear        Chapter 4: mu* and Phi against Vi (--vi 0.1,0.01) at N = 896, h_min/a = 1e-2,
//                through --strain 0.5 1.0 (transient, averaged), next to the fits of Tables 4.2
//                and 4.4, with P_cont/P.
//   cyclic       Chapter 5: alternating against biaxial compaction cycle by cycle (--cycles,
//                default 20; the thesis ran 100 in weeks), N = 224: Phi, z*, M, eps_dev.
//   cost         Time per step and per unit strain against N (224 to 57,344) at Vi = 1e-2,
//                h_min/a = 1e-2: fitted exponent, memory per grain.
//   cost3d       The same in 3D: paste_3d_shear's spheres, 512 to 13,824 (1e-3, Phi = 0.45).
//   knobs3d      The 3D factor (whole or the translations'), its refactorisation threshold and
//                the tolerance on paste_3d_shear: cost against the error in mu.
//   coarse3d     The coarse correction at h_min/a = 1e-5 and 1e-8: off, E exact, and E's weak
//                couplings dropped (lubrication.coarse_drop 1e-6 to 1e-2): cost against the error.
//   stress3d     The stress's accuracy (lubrication.stress_tolerance: off, 1e-2, 1e-4, 1e-6) at
//                h_min/a = 1e-6, 1e-9 and 1e-12: cost against the error in mu.
// Every row is appended to bench/results/paste.csv. --quick shortens every run (a smoke test).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "paste/observables.hpp"
#include "paste/solve.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"
#include "silt/statistics.hpp"

using namespace silt;

namespace {

struct Args {
  int threads = 2;
  std::string only;
  bool quick = false;
  int seeds = 5;
  int cycles = 20;                         // of each compaction test (cyclic)
  std::vector<double> vis = {1e-1, 1e-2};  // shear: the viscous numbers (--vi)
  double transient = 0.5, measured = 1.0;  // shear: strains (--strain TRANSIENT MEASURED)
  double budget = 600;                     // wall seconds per equilibration of the equilibrium section
  std::vector<std::string> sets;
};

const std::string kCsv = std::string(SILT_SOURCE_DIR) + "/bench/results/paste.csv";
const std::string kHeader =
    "date,section,case,N,h_min_over_a,cutoff,seed,Vi,solver,phi,phi_err,z_star,mobilisation,mu,mu_err,p_cont,"
    "T_P_over_eta,strain,steps,wall_s,s_per_step,solves,iters_mean,refactorisations,status,thesis";

std::string scene(const std::string& name) { return std::string(SILT_SOURCE_DIR) + "/scenes/" + name + ".toml"; }

// Rows are named with "_implicit_contacts" when the scene linearises its contacts into the solve,
// and with "_drift_max_X" when the adaptive step's drift bound is not the default 0.05.
std::string g_case_suffix;

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

Model model_of(const std::string& file, const Args& a, const std::vector<std::string>& sets) {
  std::vector<Override> o;
  for (const std::string& s : a.sets) o.push_back(parse_override(s));
  for (const std::string& s : sets) o.push_back(parse_override(s));
  Model m = compile(load_scene_file(file, o));
  const paste::PasteParams& p = m.params.get<paste::PasteParams>();
  g_case_suffix = p.implicit_contacts ? "_implicit_contacts" : "";
  if (p.drift_max != paste::PasteParams{}.drift_max) g_case_suffix += "_drift_max_" + num(p.drift_max);
  return m;
}

struct Row {
  std::string section, name, cutoff = "linear", solver = "factor_pcg", status, thesis;
  int64_t n = 0, seed = 0, steps = 0, solves = 0, refactor = 0;
  double h_min = 0, vi = 0, phi = 0, phi_err = 0, z_star = 0, mob = 0, mu = 0, mu_err = 0, p_cont = 0, time = 0,
         strain = 0, wall = 0, iters = 0;
};

void write(const Row& r) {
  std::ostringstream o;
  o << bench::today() << ',' << r.section << ',' << r.name << g_case_suffix << ',' << r.n << ',' << num(r.h_min) << ','
    << r.cutoff << ',' << r.seed << ',' << num(r.vi) << ',' << r.solver << ',' << num(r.phi) << ',' << num(r.phi_err)
    << ',' << num(r.z_star) << ',' << num(r.mob) << ',' << num(r.mu) << ',' << num(r.mu_err) << ',' << num(r.p_cont)
    << ',' << num(r.time) << ',' << num(r.strain) << ',' << r.steps << ',' << num(r.wall) << ','
    << num(r.steps ? r.wall / r.steps : 0) << ',' << r.solves << ',' << num(r.iters) << ',' << r.refactor << ','
    << r.status << ',' << r.thesis;
  bench::append_csv(kCsv, kHeader, o.str());
}

// A case of a knobs section: its name and the scene values it sets.
struct Knob {
  std::string name;
  std::vector<std::string> sets;
};

// The solver's counters of a state.
void solver_counts(const State& s, Row& r) {
  const auto& v = s.module_field(paste::paste_fields().solver);
  if (v.size() != paste::kSolverStats) return;
  r.solves = static_cast<int64_t>(v[paste::kSolves]);
  r.iters = r.solves ? v[paste::kIterationsTotal] / static_cast<double>(r.solves) : 0;
  r.refactor = static_cast<int64_t>(v[paste::kRefactorizations]);
}

const char* end_name(RunEnd e) {
  switch (e) {
    case RunEnd::kStatic: return "static";
    case RunEnd::kFailed: return "failed";
    case RunEnd::kInterrupted: return "wall_budget";
    default: return "not_static";
  }
}

// An isotropic compression of the paste to equilibrium (Peyneau sec. 2.3.2) from a prepared
// packing; fills phi, z*, M, p_cont, T, steps, wall.
// At most `budget` seconds of wall time (then status "interrupted").
void equilibrate(const Model& m, const State& packing, int threads, double max_time, Row& r, double budget = 1e9) {
  Simulation sim(m, threads);
  sim.restore(packing);
  RunOptions opt;
  opt.time = max_time;
  opt.stop_when_static = true;
  std::atomic<bool> stop{false};
  const double start = bench::now_s();
  opt.interrupt = &stop;
  opt.on_progress = [&](const State&) {
    if (bench::now_s() - start > budget) stop = true;
  };
  const RunReport rep = sim.run(opt);
  const State& s = sim.state();
  const Measurements x = measure(m, s);
  const Observer o(m, {"p_cont_ratio"});
  r.n = m.n_grains;
  r.phi = x.phi;
  r.z_star = x.z_star;
  r.mob = paste::friction_mobilisation(s);
  r.p_cont = o.sample(m, s)[0];
  r.time = s.t / m.params.get<paste::PasteParams>().time_unit;
  r.steps = rep.steps_done;
  r.wall = rep.wall_s;
  r.status = rep.end == RunEnd::kFailed ? "failed: " + s.failure.message : end_name(rep.end);
  solver_counts(s, r);
}

struct Stat {
  double mean = 0, err = 0;
};
Stat stat(const std::vector<double>& x) {
  Stat s;
  if (x.empty()) return s;
  for (double v : x) s.mean += v / static_cast<double>(x.size());
  double var = 0;
  for (double v : x) var += (v - s.mean) * (v - s.mean);
  s.err = x.size() > 1 ? std::sqrt(var / static_cast<double>(x.size() - 1)) : 0;  // spread of the samples
  return s;
}

// Table 2.3.
void iso(const Args& a) {
  std::printf("\nTable 2.3: isotropic equilibrium, N = 224, %d samples (thesis: mean +- spread of 5)\n", a.seeds);
  std::printf("%-8s %-9s %16s %14s %14s %10s %8s %8s\n", "h_min/a", "cutoff", "Phi", "z*", "M", "T P/eta", "wall s",
              "thesis");
  struct T {
    double h;
    const char* cutoff;
    const char* thesis;
  };
  const std::vector<T> cases = {{1e-3, "linear", "Phi 0.806(10) z* 3.30(3) M 0.144(7)"},
                                {1e-3, "constant", "Phi 0.806(10) z* 3.28(2) M 0.145(6)"},
                                {1e-5, "linear", "Phi 0.809(9) z* 3.41(3) M 0.123(4)"},
                                {1e-5, "constant", "Phi 0.809(10) z* 3.34(4) M 0.106(7)"}};
  std::map<int, State> packings;  // per seed: the dry packing, dilated (shared by the cases)
  for (const T& c : cases) {
    std::vector<double> phi, z, mob, time, wall;
    for (int seed = 1; seed <= a.seeds; ++seed) {
      const Model m = model_of(scene("paste_iso"), a,
                               {"scene.seed=" + std::to_string(seed), "lubrication.h_min_over_a=" + num(c.h),
                                std::string("lubrication.cutoff=\"") + c.cutoff + "\""});
      if (!packings.count(seed)) packings.emplace(seed, prepare_packing(m, a.threads));
      Row r;
      r.section = "iso";
      r.name = "table_2.3";
      r.h_min = c.h;
      r.cutoff = c.cutoff;
      r.seed = seed;
      r.thesis = c.thesis;
      equilibrate(m, packings.at(seed), a.threads, a.quick ? 20 : 1e5, r);
      write(r);
      std::printf("  seed %d: Phi %.4f z* %.3f M %.4f T %.4g (%s, %.1f s)\n", seed, r.phi, r.z_star, r.mob, r.time,
                  r.status.c_str(), r.wall);
      std::fflush(stdout);
      phi.push_back(r.phi);
      z.push_back(r.z_star);
      mob.push_back(r.mob);
      time.push_back(r.time);
      wall.push_back(r.wall);
    }
    const Stat p = stat(phi), zz = stat(z), mm = stat(mob), t = stat(time), w = stat(wall);
    std::printf("%-8.0e %-9s %8.4f+-%.4f %7.3f+-%.3f %7.4f+-%.4f %10.4g %8.1f  %s\n", c.h, c.cutoff, p.mean, p.err,
                zz.mean, zz.err, mm.mean, mm.err, t.mean, w.mean, c.thesis);
  }
  std::printf("dry bounds (thesis, N = 224): Phi 0.802 +- 0.010 (mu = 0.3), 0.836 +- 0.002 (mu = 0)\n");
}

// Table 2.2.
void equilibrium(const Args& a) {
  std::printf("\nTable 2.2: time to equilibrium, N = 224, one packing\n");
  std::printf("%-8s %10s %10s %9s %9s %8s %8s %8s  %s\n", "h_min/a", "T P/eta", "thesis", "steps", "wall s", "iters",
              "refact", "Phi", "status");
  const std::vector<std::pair<double, double>> thesis = {{1e-2, 4.69e2}, {1e-3, 2.91e2}, {1e-4, 1.71e2}, {1e-5, 2.08e3},
                                                         {1e-6, 2.45e3}, {1e-7, 2.46e4}, {1e-8, 2.41e5}};
  State packing;
  bool have = false;
  for (const auto& [h, t_thesis] : thesis) {
    const Model m = model_of(scene("paste_iso"), a, {"lubrication.h_min_over_a=" + num(h)});
    if (!have) {
      packing = prepare_packing(m, a.threads);
      have = true;
    }
    Row r;
    r.section = "equilibrium";
    r.name = "table_2.2";
    r.h_min = h;
    r.thesis = "T P/eta " + num(t_thesis);
    equilibrate(m, packing, a.threads, a.quick ? 20 : 1e7, r, a.budget);
    write(r);
    std::printf("%-8.0e %10.4g %10.4g %9lld %9.1f %8.2f %8lld %8.4f  %s\n", h, r.time, t_thesis,
                static_cast<long long>(r.steps), r.wall, r.iters, static_cast<long long>(r.refactor), r.phi,
                r.status.c_str());
    std::fflush(stdout);
  }
}

// The adaptive step's threshold and the solver, at h_min/a = 1e-3.
void knobs(const Args& a) {
  std::printf("\nKnobs at h_min/a = 1e-3, N = 224, one packing: cost against the equilibrium reached\n");
  std::printf("%-34s %9s %9s %9s %8s %8s %8s %8s\n", "case", "T P/eta", "steps", "wall s", "iters", "refact", "Phi",
              "z*");
  const std::vector<Knob> cases = {
      {"dt_change=0.003", {"lubrication.dt_change=0.003"}},
      {"dt_change=0.01 (default)", {}},
      {"dt_change=0.03", {"lubrication.dt_change=0.03"}},
      {"dt_change=0.1", {"lubrication.dt_change=0.1"}},
      {"dt_growth=1.5", {"lubrication.dt_growth=1.5"}},
      {"solver=direct", {"lubrication.solver=\"direct\""}},
      {"solver=factor_pcg refactor 5", {"lubrication.refactor_iterations=5"}},
      {"solver=factor_pcg refactor 40", {"lubrication.refactor_iterations=40"}},
      {"solver=factor_pcg every 10 solves", {"lubrication.refactor_every=10"}},
      {"solver=factor_pcg every 100 solves", {"lubrication.refactor_every=100"}},
      {"solver=cg (Jacobi)", {"lubrication.solver=\"cg\"", "lubrication.max_iterations=100000"}},
  };
  State packing;
  bool have = false;
  for (const Knob& k : cases) {
    std::vector<std::string> sets = k.sets;
    sets.push_back("lubrication.h_min_over_a=1e-3");
    const Model m = model_of(scene("paste_iso"), a, sets);
    if (!have) {
      packing = prepare_packing(m, a.threads);
      have = true;
    }
    Row r;
    r.section = "knobs";
    r.name = k.name;
    r.h_min = 1e-3;
    r.solver = linalg::method_name(m.params.get<paste::PasteParams>().solver.method);
    equilibrate(m, packing, a.threads, a.quick ? 20 : 1e5, r);
    write(r);
    std::printf("%-34s %9.4g %9lld %9.1f %8.2f %8lld %8.4f %8.3f  %s\n", k.name.c_str(), r.time,
                static_cast<long long>(r.steps), r.wall, r.iters, static_cast<long long>(r.refactor), r.phi, r.z_star,
                r.status.c_str());
    std::fflush(stdout);
  }
}

// A sheared paste from its prepared packing: through `transient` of strain, then averaged over
// `measured` of strain (samples every 0.002 of strain; mu's samples also into `mu_samples`).
Row shear_run(const Model& m, const State& packing, int threads, double transient, double measured,
              std::vector<double>* mu_samples = nullptr) {
  Simulation sim(m, threads);
  sim.restore(packing);
  Row r;
  r.n = m.n_grains;
  const bool pressure = m.box_control.on;  // else a fixed volume: no Vi, no P_cont / P
  r.vi = pressure ? m.params.get<paste::PasteParams>().eta * m.shear.rate / m.box_control.pressure : 0;
  const double t0 = bench::now_s();
  RunOptions opt;
  opt.time = transient / m.shear.rate;
  RunReport rep = sim.run(opt);
  std::vector<double> mu, phi, pc;
  const Observer o(
      m, pressure ? std::vector<std::string>{"mu", "phi", "p_cont_ratio"} : std::vector<std::string>{"mu", "phi"});
  opt.time = 0.002 / m.shear.rate;
  int64_t steps = rep.steps_done;
  const double t_measure = sim.state().t;
  while (rep.end == RunEnd::kDone && sim.state().shear_strain < transient + measured) {
    rep = sim.run(opt);
    steps += rep.steps_done;
    const auto v = o.sample(m, sim.state());
    mu.push_back(v[0]);
    phi.push_back(v[1]);
    if (pressure) pc.push_back(v[2]);
  }
  r.wall = bench::now_s() - t0;
  r.steps = steps;
  r.strain = sim.state().shear_strain;
  r.time = (sim.state().t - t_measure) / m.params.get<paste::PasteParams>().time_unit;
  r.status = rep.end == RunEnd::kFailed ? "failed: " + sim.state().failure.message : "ok";
  const BlockAverage bm = block_average(mu), bp = block_average(phi), bc = block_average(pc);
  r.mu = bm.mean;
  r.mu_err = bm.err;
  r.phi = bp.mean;
  r.phi_err = bp.err;
  r.p_cont = bc.mean;
  r.z_star = measure(m, sim.state()).z_star;
  r.mob = paste::friction_mobilisation(sim.state());
  solver_counts(sim.state(), r);
  if (mu_samples) *mu_samples = mu;
  return r;
}

// Chapter 4.
void shear(const Args& a) {
  std::printf("\nChapter 4: mu*(Vi) and Phi(Vi), N = 896, h_min/a = 1e-2 (fits of Tables 4.2 and 4.4)\n");
  std::printf("%-8s %16s %8s %16s %8s %8s %8s %9s %9s  %s\n", "Vi", "mu*", "fit", "Phi", "fit", "P_cont/P", "strain",
              "steps", "wall s", "status");
  const std::vector<double> vis = a.quick ? std::vector<double>{1e-1} : a.vis;
  State packing;
  bool have = false;
  for (double vi : vis) {
    const Model m = model_of(scene("paste_shear"), a, {"shear.viscous_number=" + num(vi)});
    if (!have) {
      packing = prepare_packing(m, a.threads);
      have = true;
    }
    const double transient = a.quick ? 0.01 : a.transient, measured = a.quick ? 0.01 : a.measured;
    Row r = shear_run(m, packing, a.threads, transient, measured);
    r.section = "shear";
    r.name = "ch4";
    r.h_min = 1e-2;
    const double mu_fit = 0.213 + 0.285 * std::pow(vi, 0.22);
    const double phi_fit = 1 / (1 / 0.817 + 0.530 * std::pow(vi, 0.49));
    r.thesis = "mu* " + num(mu_fit) + " Phi " + num(phi_fit);
    write(r);
    std::printf("%-8.0e %8.4f+-%.4f %8.4f %8.4f+-%.4f %8.4f %8.3f %8.2f %9lld %9.1f  %s\n", vi, r.mu, r.mu_err, mu_fit,
                r.phi, r.phi_err, phi_fit, r.p_cont, r.strain, static_cast<long long>(r.steps), r.wall,
                r.status.c_str());
    std::fflush(stdout);
  }
}

// k x k copies of a prepared periodic packing, as a state of `m` (a model of k^2 times the grains
// in a box k times as long): large packings without the dry compression of each.
State tile(const Model& m, const State& p, int k) {
  State s = make_state(m);
  const int D = p.dim, R = p.rot;
  int64_t i = 0;
  const int kz = D == 3 ? k : 1;
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b)
      for (int z = 0; z < kz; ++z)
        for (int64_t g = 0; g < p.n; ++g, ++i) {
          const int shift[3] = {a, b, z};
          for (int c = 0; c < D; ++c) s.particle_x[D * i + c] = p.particle_x[D * g + c] + shift[c] * p.box.len[c];
          s.particle_r[i] = p.particle_r[g];
          s.particle_inv_m[i] = p.particle_inv_m[g];
          s.particle_inv_i[i] = p.particle_inv_i[g];
          for (int c = 0; c < D; ++c) s.particle_v[D * i + c] = 0;
          for (int c = 0; c < R; ++c) s.particle_w[R * i + c] = 0;
        }
  for (int a = 0; a < D; ++a) s.box.len[a] = k * p.box.len[a];
  s.nbr_valid = false;
  return s;
}

// Chapter 5: cycle by cycle, Phi, z*, M and the deviatoric strain (L_x - L_y changes) of both tests
// from one packing.
void cyclic(const Args& a) {
  const int cycles = a.quick ? 1 : a.cycles;
  std::printf(
      "\nChapter 5: alternating against biaxial compaction, N = 224, h_min/a = 1e-2, Vi = 0.1, dP/P = 0.1, "
      "%d cycles\n",
      cycles);
  std::printf("%6s | %9s %7s %7s %9s | %9s %7s %7s %9s\n", "cycle", "alt Phi", "z*", "M", "eps_dev", "biax Phi", "z*",
              "M", "eps_dev");
  std::vector<std::vector<Row>> rows(2);
  State packing;
  bool have = false;
  const char* kinds[2] = {"alternating", "biaxial"};
  for (int k = 0; k < 2; ++k) {
    const Model m = model_of(scene("paste_cyclic_alternating"), a, {std::string("box.cycle=\"") + kinds[k] + "\""});
    if (!have) {
      packing = prepare_packing(m, a.threads);
      have = true;
    }
    Simulation sim(m, a.threads);
    sim.restore(packing);
    const double period = 2 * std::numbers::pi / m.box_control.cycle_omega;
    const double lx0 = packing.box.len[0], ly0 = packing.box.len[1];
    const double t0 = bench::now_s();
    for (int c = 1; c <= cycles; ++c) {
      RunOptions opt;
      opt.time = period;
      const RunReport rep = sim.run(opt);
      Row r;
      r.section = "cyclic";
      r.name = kinds[k];
      r.h_min = 1e-2;
      r.vi = 0.1;
      r.n = m.n_grains;
      r.strain = c;  // the cycle
      const State& s = sim.state();
      const Measurements x = measure(m, s, measure_part::kGrains | measure_part::kContacts);
      r.phi = x.phi;
      r.z_star = x.z_star;
      r.mob = paste::friction_mobilisation(s);
      // eps_11 - eps_22, eps_ii = (L_i^0 - L_i) / L_i^0 (Peyneau sec. 5.3.1).
      r.mu = (lx0 - s.box.len[0]) / lx0 - (ly0 - s.box.len[1]) / ly0;
      r.wall = bench::now_s() - t0;
      r.steps = s.step;
      r.status = rep.end == RunEnd::kFailed ? "failed: " + s.failure.message : "ok";
      solver_counts(s, r);
      write(r);
      rows[k].push_back(r);
      if (rep.end == RunEnd::kFailed) break;
    }
  }
  for (size_t c = 0; c < std::min(rows[0].size(), rows[1].size()); ++c)
    std::printf("%6zu | %9.5f %7.3f %7.4f %9.2e | %9.5f %7.3f %7.4f %9.2e\n", c + 1, rows[0][c].phi, rows[0][c].z_star,
                rows[0][c].mob, rows[0][c].mu, rows[1][c].phi, rows[1][c].z_star, rows[1][c].mob, rows[1][c].mu);
  for (int k = 0; k < 2; ++k)
    if (!rows[k].empty())
      std::printf("%s: %lld steps, %.1f s wall\n", kinds[k], static_cast<long long>(rows[k].back().steps),
                  rows[k].back().wall);
}

// The least-squares slope of log y against log x.
double fitted_exponent(const std::vector<double>& lx, const std::vector<double>& ly) {
  const size_t points = lx.size();
  double mx = 0, my = 0;
  for (size_t i = 0; i < points; ++i) {
    mx += lx[i] / static_cast<double>(points);
    my += ly[i] / static_cast<double>(points);
  }
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < points; ++i) {
    sxy += (lx[i] - mx) * (ly[i] - my);
    sxx += (lx[i] - mx) * (lx[i] - mx);
  }
  return sxy / sxx;
}

// One row of a cost table, printed; its point (log N, log cost per unit strain) kept for the fit.
void cost_row(Row& r, int64_t n, double rss0, std::vector<double>& lx, std::vector<double>& ly) {
  write(r);
  const double per_step = r.wall / static_cast<double>(std::max<int64_t>(1, r.steps));
  const double per_strain = r.wall / r.strain;
  lx.push_back(std::log(static_cast<double>(n)));
  ly.push_back(std::log(per_strain));
  std::printf("%8lld %12.4g %14.4g %12.4g %10.2f %8lld %8.1f %12.3g\n", static_cast<long long>(n), per_step, per_strain,
              static_cast<double>(r.steps) / r.strain, r.iters, static_cast<long long>(r.refactor), r.wall,
              std::max(rss0, bench::peak_rss_bytes()) / 1e6 / static_cast<double>(n));
  std::fflush(stdout);
}

const char* kCostHeader = "%8s %12s %14s %12s %10s %8s %8s %12s\n";

// Cost against N in 3D: paste_3d_shear's spheres (Phi = 0.45, gammadot = 0.01, h_min/a = 1e-3),
// a packing of 512 tiled k x k x k.
void cost3d(const Args& a) {
  const double strain = a.quick ? 0.005 : 0.05;
  std::printf("\nCost against N in 3D: paste_3d_shear, packings of 512 spheres tiled k x k x k, %g of strain\n",
              strain);
  std::printf(kCostHeader, "N", "s/step", "s/unit strain", "steps/strain", "iters", "refact", "wall s", "MB/grain");
  const Model base = model_of(scene("paste_3d_shear"), a, {"grains.0.count=512", "domain.hi=[19.0,19.0,19.0]"});
  const State packing = prepare_packing(base, a.threads);
  std::vector<double> lx, ly;
  for (int k : a.quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 3}) {
    const int64_t n = base.n_grains * k * k * k;
    const std::string side = num(19.0 * k);
    const Model m =
        model_of(scene("paste_3d_shear"), a,
                 {"grains.0.count=" + std::to_string(n), "domain.hi=[" + side + "," + side + "," + side + "]"});
    const State tiled = tile(m, packing, k);
    const double rss0 = bench::peak_rss_bytes();
    Row r = shear_run(m, tiled, a.threads, strain, 0);
    r.section = "cost3d";
    r.name = "N";
    r.h_min = m.params.get<paste::PasteParams>().h_min_over_a;
    cost_row(r, n, rss0, lx, ly);
  }
  std::printf("cost per unit strain ~ N^%.2f (target <= 1.5 in 3D; the thesis: 2.5)\n", fitted_exponent(lx, ly));
}

// Rows of cases on paste_3d_shear from one packing (`base` and each case's settings over the
// scene's): cost against the error in mu, each sample against the first case's (the reference).
void knob_table(const Args& a, const char* section, double strain, const std::vector<std::string>& base,
                const std::vector<Knob>& cases) {
  std::printf("%-36s %8s %9s %8s %8s %12s  %s\n", "case", "steps", "wall s", "iters", "refact", "max |dmu|", "status");
  auto sets = [&](const std::vector<std::string>& own) {
    std::vector<std::string> all = base;
    all.insert(all.end(), own.begin(), own.end());
    return all;
  };
  const State packing = prepare_packing(model_of(scene("paste_3d_shear"), a, sets({})), a.threads);
  std::vector<double> reference;
  for (const Knob& k : cases) {
    const Model m = model_of(scene("paste_3d_shear"), a, sets(k.sets));
    std::vector<double> mu;
    Row r = shear_run(m, packing, a.threads, 0, strain, &mu);
    if (reference.empty()) reference = mu;
    double err = 0;
    for (size_t i = 0; i < mu.size() && i < reference.size(); ++i) err = std::max(err, std::abs(mu[i] - reference[i]));
    if (mu.size() != reference.size()) err = std::numeric_limits<double>::quiet_NaN();
    r.section = section;
    r.name = k.name;
    r.h_min = m.params.get<paste::PasteParams>().h_min_over_a;
    r.thesis = "max |mu - mu_ref| " + num(err) + " over " + std::to_string(mu.size()) + " samples";
    write(r);
    std::printf("%-36s %8lld %9.1f %8.2f %8lld %12.3g  %s\n", k.name.c_str(), static_cast<long long>(r.steps), r.wall,
                r.iters, static_cast<long long>(r.refactor), err, r.status.c_str());
    std::fflush(stdout);
  }
}

// The 3D factor's knobs: which factor (the whole Xi, or the translations' with each rotation's
// own block) and when it is refactorised, and the tolerance, on paste_3d_shear at its h_min/a =
// 1e-3: cost against the error in mu (each sample against a run of the whole factor to 1e-12).
void knobs3d(const Args& a) {
  const double strain = a.quick ? 0.004 : 0.07;
  std::printf("\n3D factor knobs: paste_3d_shear (4,096 spheres, h_min/a = 1e-3), %g of strain\n", strain);
  const std::string whole = "lubrication.factor_rotations=\"whole\"";
  knob_table(a, "knobs3d", strain, {},
             {
                 {"reference: whole; tolerance 1e-12", {whole, "lubrication.tolerance=1e-12"}},
                 {"whole; refactor 15", {whole}},
                 {"own; refactor 20", {"lubrication.refactor_iterations=20"}},
                 {"own; refactor 25", {"lubrication.refactor_iterations=25"}},
                 {"own; refactor 30 (default)", {}},
                 {"own; refactor 40", {"lubrication.refactor_iterations=40"}},
                 {"own; refactor 60", {"lubrication.refactor_iterations=60"}},
                 // (the residual's tolerance alone: the stress's check off, which would take these on)
                 {"own; tolerance 1e-6", {"lubrication.tolerance=1e-6", "lubrication.stress_tolerance=0"}},
                 {"own; tolerance 1e-4", {"lubrication.tolerance=1e-4", "lubrication.stress_tolerance=0"}},
                 {"whole; tolerance 1e-4", {whole, "lubrication.tolerance=1e-4", "lubrication.stress_tolerance=0"}},
                 {"own; tolerance 1e-4, stress 1e-4", {"lubrication.tolerance=1e-4"}},
             });
}

// The coarse correction's knobs at small gaps (h_min/a = 1e-5 and 1e-8): without it, and with E
// exact or its weak couplings dropped below 1e-6 to 1e-2 of its diagonal (coarse_drop).
void coarse3d(const Args& a) {
  const double strain = a.quick ? 0.002 : 0.02;
  for (const char* gap : {"1e-5", "1e-8"}) {
    std::printf("\nCoarse correction knobs: paste_3d_shear (4,096 spheres, h_min/a = %s), %g of strain\n", gap, strain);
    knob_table(
        a, "coarse3d", strain, {std::string("lubrication.h_min_over_a=") + gap},
        {
            {"reference: E exact; tolerance 1e-12", {"lubrication.coarse_drop=0", "lubrication.tolerance=1e-12"}},
            {"no correction", {"lubrication.coarse_ratio=0"}},
            {"E exact", {"lubrication.coarse_drop=0"}},
            {"drop 1e-6", {"lubrication.coarse_drop=1e-6"}},
            {"drop 1e-4 (default)", {}},
            {"drop 1e-3", {"lubrication.coarse_drop=1e-3"}},
            {"drop 1e-2", {"lubrication.coarse_drop=1e-2"}},
        });
  }
}

// The stress's accuracy at small gaps, where the lubrication multiplies the velocities' error by
// up to a / h_min: the solve to the residual's tolerance alone (1e-8), and taken on until the
// stress's estimated error is below 1e-2, 1e-4 (the default) or 1e-6 of it; each sample of mu
// against a run to a residual of 1e-13 and a stress to 1e-8 (as far as round-off lets it).
void stress3d(const Args& a) {
  const double strain = a.quick ? 0.002 : 0.01;
  for (const char* gap : {"1e-6", "1e-9", "1e-12"}) {
    std::printf("\nStress accuracy: paste_3d_shear (4,096 spheres, h_min/a = %s), %g of strain\n", gap, strain);
    knob_table(a, "stress3d", strain, {std::string("lubrication.h_min_over_a=") + gap},
               {
                   {"reference: tolerance 1e-13, stress 1e-8",
                    {"lubrication.tolerance=1e-13", "lubrication.stress_tolerance=1e-8"}},
                   {"stress check off", {"lubrication.stress_tolerance=0"}},
                   {"stress 1e-2", {"lubrication.stress_tolerance=1e-2"}},
                   {"stress 1e-4 (default)", {}},
                   {"stress 1e-6", {"lubrication.stress_tolerance=1e-6"}},
               });
  }
}

// Cost against N.
void cost(const Args& a) {
  std::printf("\nCost against N: Vi = 1e-2, h_min/a = 1e-2, a packing of 224 and packings of 896 tiled k x k, %s\n",
              a.quick ? "0.002 of strain" : "0.02 of strain");
  std::printf(kCostHeader, "N", "s/step", "s/unit strain", "steps/strain", "iters", "refact", "wall s", "MB/grain");
  const Model base = model_of(scene("paste_shear"), a, {});
  const State packing = prepare_packing(base, a.threads);
  std::vector<int> ks = {1, 2, 4};
  if (!a.quick) ks.push_back(8);
  std::vector<double> lx, ly;
  const double strain = a.quick ? 0.002 : 0.02;
  // One row: the sheared run of `start`, its cost per step and per unit strain, its memory.
  auto measure = [&](const Model& m, const State& start) {
    const double rss0 = bench::peak_rss_bytes();
    Row r = shear_run(m, start, a.threads, strain, 0);
    r.section = "cost";
    r.name = "N";
    r.h_min = 1e-2;
    cost_row(r, m.n_grains, rss0, lx, ly);
  };
  // N = 224 (the thesis' isotropic samples): a packing of its own, prepared as the scene's, in a
  // box of a quarter of the area.
  const Model small = model_of(scene("paste_shear"), a, {"grains.0.count=224", "domain.hi=[16.0,16.0]"});
  measure(small, prepare_packing(small, a.threads));
  for (int k : ks) {
    const int64_t n = base.n_grains * k * k;
    const double side = 34.0 * k;  // room for the random placement the model is compiled with
    const Model m = model_of(scene("paste_shear"), a,
                             {"grains.0.count=" + std::to_string(n), "domain.hi=[" + num(side) + "," + num(side) + "]",
                              "prepare.compress=false", "prepare.dilation=1.0"});
    measure(m, tile(m, packing, k));
  }
  std::printf("cost per unit strain ~ N^%.2f (target <= 1.2 in 2D; the thesis: 2.5)\n", fitted_exponent(lx, ly));
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] {
    Args a;
    for (int i = 1; i < argc; ++i) {
      const std::string s = argv[i];
      if (s == "--threads" && i + 1 < argc) a.threads = std::atoi(argv[++i]);
      else if (s == "--only" && i + 1 < argc) a.only = argv[++i];
      else if (s == "--seeds" && i + 1 < argc) a.seeds = std::atoi(argv[++i]);
      else if (s == "--quick") a.quick = true;
      else if (s == "--cycles" && i + 1 < argc) a.cycles = std::atoi(argv[++i]);
      else if (s == "--vi" && i + 1 < argc) a.vis = bench::parse_list(argv[++i]);
      else if (s == "--strain" && i + 2 < argc) {
        a.transient = std::atof(argv[++i]);
        a.measured = std::atof(argv[++i]);
      } else if (s == "--budget" && i + 1 < argc) a.budget = std::atof(argv[++i]);
      else if (s == "--set" && i + 1 < argc) a.sets.push_back(argv[++i]);
      else throw std::invalid_argument("unknown option " + s);
    }
    const std::vector<std::pair<std::string, void (*)(const Args&)>> sections = {
        {"iso", iso},          {"equilibrium", equilibrium}, {"knobs", knobs},
        {"shear", shear},      {"cyclic", cyclic},           {"cost", cost},
        {"cost3d", cost3d},    {"knobs3d", knobs3d},         {"coarse3d", coarse3d},
        {"stress3d", stress3d}};
    std::vector<std::string> names;
    for (const auto& section : sections) names.push_back(section.first);
    bench::check_only(a.only, names);
    std::printf("paste bench on %s (%s), %d thread(s)%s\n", bench::host().c_str(), bench::cpu_model().c_str(),
                a.threads, a.quick ? ", quick" : "");
    for (const auto& [name, fn] : sections)
      if (a.only.empty() || a.only == name) fn(a);
    return 0;
  });
}
