// Validation and speed of the resolved fluid (engine/fluid/), written to bench/results/fluid*.csv:
//
//   cavity      the lid-driven cavity at Re = 100, 400, 1000 on 64^2, 128^2, 256^2 cells, run to a
//               steady state, against the centreline profiles of Ghia, Ghia & Shin (1982), with the
//               cost of each: the fluid's first speed-accuracy table
//   throughput  cell-steps per second at 1 and 2 threads, 2D and 3D, 32^3 to 256^3, the bytes a
//               step must move and a triad bandwidth measured beside each case (paired rounds)
//   openfoam    the cavity at 128^2, Re = 10, dt = 0.005 L/U, against OpenFOAM's icoFoam
//               (bench/openfoam/run_icofoam.sh) in the same run, both against a fine silt grid
//   frames      a vorticity frame of the 2D cavity at 1024 x 1024 pixels and a 3D slice, timed
//   poisson     one Poisson solve on 128^3 cells by the fast transforms and by multigrid CG to 1e-8
//   viscous     the viscous schemes (explicit, Crank-Nicolson, backward Euler) on the decaying
//               Taylor-Green vortex at Re = 100, 1 and 1e-3: steps, time and error of each
//
//   build/bench/fluid [--only cavity|throughput|openfoam|frames|poisson|viscous] [--quick] [--simd LEVELS]
// (--quick: the smaller cases only, 32^3 for poisson. --simd avx2,avx512: the kernels' vector
// instructions, each level in turn for every throughput case, side by side; by default the
// processor's widest.)
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "core/simd_level.hpp"
#include "fluid/fast_solver.hpp"
#include "fluid/module.hpp"
#include "fluid/multigrid.hpp"
#include "fluid/pressure_solve.hpp"
#include "fluid/step.hpp"
#include "silt/render.hpp"
#include "silt/simulation.hpp"

using namespace silt;
using namespace silt::bench;

namespace {

constexpr int kRounds = 5;  // timed rounds of each throughput case

const std::string kResults = std::string(SILT_SOURCE_DIR) + "/bench/results/";

std::string num(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

// The 2D (or 3D) lid-driven cavity of side 1 with a lid of speed 1.
std::string cavity_scene(int dim, int n, double re, const std::string& extra) {
  const bool d3 = dim == 3;
  const std::string c = std::to_string(n);
  return std::string("[scene]\ndimension = ") + (d3 ? "3" : "2") +
         "\n[domain]\nlo = " + (d3 ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]") +
         "\nhi = " + (d3 ? "[1.0, 1.0, 1.0]" : "[1.0, 1.0]") + "\n[fluid]\ncells = [" + c + ", " + c +
         (d3 ? ", " + c : "") + "]\nreynolds = " + num(re) + "\n" + extra +
         "\n[fluid.boundary]\ny_hi_velocity = " + (d3 ? "[1.0, 0.0, 0.0]" : "[1.0, 0.0]") + "\n";
}

std::string taylor_green_scene(int dim, int n, const std::string& viscous, double re = 1600) {
  const bool d3 = dim == 3;
  const std::string c = std::to_string(n);
  return std::string("[scene]\ndimension = ") + (d3 ? "3" : "2") +
         "\n[domain]\nlo = " + (d3 ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]") +
         "\nhi = " + (d3 ? "[1.0, 1.0, 1.0]" : "[1.0, 1.0]") +
         "\nperiodic = " + (d3 ? "[true, true, true]" : "[true, true]") + "\n[fluid]\ncells = [" + c + ", " + c +
         (d3 ? ", " + c : "") + "]\nreynolds = " + num(re) + "\ninitial = \"taylor_green\"\nviscous = \"" + viscous +
         "\"\n";
}

Model model_of(const std::string& toml) { return compile(parse_scene(toml, "bench.toml")); }

// A published profile: coordinate, then one column per Reynolds number (bench/data/ghia1982_*.csv).
struct Table {
  std::vector<double> x;
  std::vector<std::vector<double>> cols;
};
Table read_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  Table t;
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::stringstream ss(line);
    std::string cell;
    std::vector<double> row;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    t.x.push_back(row[0]);
    if (t.cols.size() < row.size() - 1) t.cols.resize(row.size() - 1);
    for (size_t k = 1; k < row.size(); ++k) t.cols[k - 1].push_back(row[k]);
  }
  return t;
}

// Runs until the velocity changes by less than `tol` (max over faces, per unit time) over a
// window of two time units, or until t_max. Returns the wall time.
double run_to_steady(Simulation& sim, double t_max, double tol) {
  const double t0 = now_s();
  const auto ufield = fluid::fluid_fields().u[0];
  std::vector<double> before = sim.state().module_field(ufield);
  double next = 2;
  while (sim.state().t < t_max) {
    sim.state().boundary_seen = false;
    if (!sim.step()) throw std::runtime_error("the run failed: " + sim.state().failure.message);
    if (sim.state().t >= next) {
      const auto& now = sim.state().module_field(ufield);
      double change = 0;
      for (size_t i = 0; i < now.size(); ++i) change = std::max(change, std::abs(now[i] - before[i]));
      before = now;
      next = sim.state().t + 2;
      if (change / 2 < tol) break;
    }
  }
  return now_s() - t0;
}

// Largest and RMS differences of a probe from a table column at the table's points.
std::pair<double, double> profile_error(const Model& m, const State& s, const std::string& field, bool vertical,
                                        const Table& t, int col) {
  const fluid::FluidParams& p = m.params.get<fluid::FluidParams>();
  double mx = 0, sq = 0;
  for (size_t k = 0; k < t.x.size(); ++k) {
    // Ghia's Re = 400 v at x = 0.9063 (-0.23827) breaks its column's trend: a misprint, left out.
    if (!vertical && col == 1 && std::abs(t.x[k] - 0.9063) < 1e-4) continue;
    const std::array<double, 3> x =
        vertical ? std::array<double, 3>{0.5, t.x[k], 0} : std::array<double, 3>{t.x[k], 0.5, 0};
    const double d = fluid::sample(p, s, field, x) - t.cols[col][k];
    mx = std::max(mx, std::abs(d));
    sq += d * d;
  }
  return {mx, std::sqrt(sq / static_cast<double>(t.x.size() - (!vertical && col == 1 ? 1 : 0)))};
}

void cavity(bool quick) {
  const Table gu = read_table(std::string(SILT_SOURCE_DIR) + "/bench/data/ghia1982_u.csv");
  const Table gv = read_table(std::string(SILT_SOURCE_DIR) + "/bench/data/ghia1982_v.csv");
  const std::string header =
      "date,re,cells,viscous,steps,t_end,wall_s,cell_steps_per_s,u_err_max,u_err_rms,v_err_max,v_err_rms";
  std::printf("\nLid-driven cavity against Ghia et al. (1982), centreline profiles, to a steady state\n");
  std::printf("%6s %6s %-15s %8s %7s %8s %10s %9s %9s %9s %9s\n", "Re", "cells", "viscous", "steps", "t_end", "wall_s",
              "cells/s", "u_max", "u_rms", "v_max", "v_rms");
  struct Case {
    double re;
    int n;
    std::string viscous;
  };
  std::vector<Case> cases;
  const double res[3] = {100, 400, 1000};
  for (int r = 0; r < 3; ++r)
    for (int n : {64, 128, 256})
      if (!quick || n <= 64) cases.push_back({res[r], n, "crank_nicolson"});
  if (!quick) cases.push_back({100, 128, "explicit"});  // the steady state without CN's O(dt) wall term
  for (const Case& c : cases) {
    const int col = c.re == 100 ? 0 : (c.re == 400 ? 1 : 2);
    Simulation sim(model_of(cavity_scene(2, c.n, c.re, "viscous = \"" + c.viscous + "\"\ncfl = 0.5")), 2);
    const double wall = run_to_steady(sim, c.re == 1000 ? 120 : 80, 1e-6);
    const auto eu = profile_error(sim.model(), sim.state(), "u", true, gu, col);
    const auto ev = profile_error(sim.model(), sim.state(), "v", false, gv, col);
    const double rate = static_cast<double>(c.n) * c.n * static_cast<double>(sim.state().step) / wall;
    std::printf("%6.0f %6d %-15s %8lld %7.1f %8.1f %10.3g %9.4f %9.4f %9.4f %9.4f\n", c.re, c.n, c.viscous.c_str(),
                static_cast<long long>(sim.state().step), sim.state().t, wall, rate, eu.first, eu.second, ev.first,
                ev.second);
    append_csv(kResults + "fluid.csv", header,
               today() + "," + num(c.re) + "," + std::to_string(c.n) + "," + c.viscous + "," +
                   std::to_string(sim.state().step) + "," + num(sim.state().t) + "," + num(wall) + "," + num(rate) +
                   "," + num(eu.first) + "," + num(eu.second) + "," + num(ev.first) + "," + num(ev.second));
  }
}

// The viscous schemes from Re = 100 down to Re << 1: the 2D Taylor-Green vortex (U0 = 1 in a
// periodic unit square, 64^2 cells, the adaptive step at CFL 0.5) run until its velocity has
// decayed by e^-5, t = 5 / (2 nu k^2), k = 2 pi (the last step may pass it); the largest error of
// u over the x faces against the exact decay at the time reached, relative to U0 and to the
// amplitude then (which a first-order scheme with a step of many decay times cannot follow, while
// its velocity is as near zero as the exact one). The explicit scheme's step is held by its
// stability (nu dt sum 1/h^2 <= 0.54), Crank-Nicolson's by its damping of the box's longest
// wavelength (nu dt k^2 <= 1), backward Euler's by the CFL number alone. The grid's own error
// (its Laplacian's eigenvalue, 8 sin^2(k h / 2) / h^2 against 2 k^2) is 0.4 % of the amplitude
// at that time: a floor under every row.
void viscous_schemes() {
  const std::string header = "date,re,cells,viscous,steps,t_end,dt_last,wall_s,err_over_u0,err_over_amplitude";
  std::printf("\nViscous schemes, Taylor-Green vortex 64^2 to a decay of e^-5, against the exact decay\n");
  std::printf("%8s %-15s %8s %10s %10s %8s %10s %10s\n", "Re", "viscous", "steps", "t_end", "dt_last", "wall_s",
              "err/U0", "err/amp");
  const int n = 64;
  const double k = 2 * std::numbers::pi, h = 1.0 / n;
  for (double re : {100.0, 1.0, 1e-3})
    for (const char* viscous : {"explicit", "crank_nicolson", "backward_euler"}) {
      Simulation sim(model_of(taylor_green_scene(2, n, viscous, re)), 2);
      const double nu = 1 / re, t_end = 5 / (2 * nu * k * k);
      const double t0 = now_s();
      while (sim.state().t < t_end * (1 - 1e-12))
        if (!sim.step()) throw std::runtime_error("the run failed: " + sim.state().failure.message);
      const double wall = now_s() - t0;
      const auto& u = sim.state().module_field(fluid::fluid_fields().u[0]);
      const auto d = sim.model().params.get<fluid::FluidParams>().grid.face_dims(0);
      const double amp = std::exp(-2 * nu * k * k * sim.state().t);
      double err = 0;
      for (int64_t j = 0; j < d[1]; ++j)
        for (int64_t i = 0; i < d[0]; ++i)
          err = std::max(err, std::abs(u[i + d[0] * j] - std::sin(k * i * h) * std::cos(k * (j + 0.5) * h) * amp));
      std::printf("%8.3g %-15s %8lld %10.4g %10.4g %8.3f %10.3g %10.3g\n", re, viscous,
                  static_cast<long long>(sim.state().step), sim.state().t, sim.state().dt, wall, err, err / amp);
      append_csv(kResults + "fluid_viscous.csv", header,
                 today() + "," + num(re) + "," + std::to_string(n) + "," + viscous + "," +
                     std::to_string(sim.state().step) + "," + num(sim.state().t) + "," + num(sim.state().dt) + "," +
                     num(wall) + "," + num(err) + "," + num(err / amp));
    }
}

// Triad a = b + 3 c over 2^25 doubles (256 MiB each array): the bandwidth the machine gives
// [B/s], 24 bytes per element (write-allocate not counted, as in STREAM), best of `reps` passes
// after one untimed one, on `threads` threads.
class Triad {
 public:
  Triad() : a_(kN, 1), b_(kN, 2), c_(kN, 3) {}
  double bandwidth(int threads, int reps) {
    tbb::task_arena arena(threads);
    double best = 1e30;
    for (int r = 0; r <= reps; ++r) {
      const double t0 = now_s();
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int64_t>(0, kN, 1 << 16), [&](const tbb::blocked_range<int64_t>& rg) {
          for (int64_t i = rg.begin(); i < rg.end(); ++i) a_[i] = b_[i] + 3.0 * c_[i];
        });
      });
      if (r > 0) best = std::min(best, now_s() - t0);
    }
    return 24.0 * static_cast<double>(kN) / best;
  }

 private:
  static constexpr int64_t kN = int64_t{1} << 25;
  std::vector<double> a_, b_, c_;
};

// "avx2,avx512" -> the levels, in that order.
std::vector<SimdLevel> simd_levels(const std::string& list) {
  std::vector<SimdLevel> out;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');)
    if (!simd_level_named(name, out.emplace_back()))
      throw std::invalid_argument("--simd: unknown level '" + name + "' (baseline, avx2, avx512)");
  if (out.empty()) throw std::invalid_argument("--simd: no level given");
  return out;
}

// Doubles a step must read and write per cell, as implemented (fluid/step.cpp), for the
// Taylor-Green vortex of the throughput cases (every axis periodic), each sweep counted once over
// the grid: its stencils' neighbours and the rows of ghosts the boundaries fill (a few rows or
// planes, O(1/n) of the data) come from caches that hold a few planes. A "pass" reads and writes
// every cell: 2.
//
// Per Runge-Kutta substep:
//   fluid_momentum   one fused sweep: reads u (D components), the pressure so far and n_prev (D);
//                    writes u* (D) and n_prev (D): 4D + 1. With Crank-Nicolson it also reads the
//                    boundary Laplacian bc_lap (D; operators.cpp, MomentumPoint): 5D + 1
//   fluid_viscous    (Crank-Nicolson) per component: the Helmholtz solve, whose first pass reads
//                    the padded u* (dividing by beta) and whose last writes it back: solve
//   fluid_pressure   the divergence (reads D, writes 1), the Poisson solve, whose last pass writes
//                    the increment into its padded array: D + 1 + solve
//   fluid_project    one fused sweep: reads the increment once, reads and writes u (2D) and the
//                    pressure (2): 2D + 3
// A solve (fast_solver.cpp) is three passes: x forward (in 3D, x then y forward, one z plane at
// a time, the plane staying in the cache between the two), the last axis forward, divided by the
// eigenvalues and back in one pass (blocks gathered into a buffer), and x back (in 3D, y then x,
// plane by plane). When the last axis is not periodic (a wall), the Thomas sweeps along it
// replace that pass, forward and back over a chunk of 64 modes that stays in cache between the
// two (64 x n values and as many pivots): again 3 passes.
// Per step: fluid_load copies the State's velocity and pressure into the padded arrays and
// fluid_store copies them back (read, write, D + 1 arrays each): 4D + 4.
// Not counted: the divergence the store computes only when a sample looks at the step (the
// throughput runs take none); and the ghost fills, 7D + 6 a step (velocity and pressure before
// each momentum sweep, velocity before each divergence, the increment before each projection,
// velocity in the store), which along y and z write whole rows or planes of ghosts but along x
// touch the two ends of every row, about 4 of its (n + 3) / 8 cache lines: some 2 x 32 / n
// doubles per cell each, 10 % more than counted at 128^3 in 3D and 1 % at 1024^2.
double doubles_per_cell_step(int dim, bool cn) {
  const double D = dim;
  const double solve = 2 * 3;
  double substep = (cn ? 5 * D + 1 : 4 * D + 1) + (D + 1 + solve) + (2 * D + 3);
  if (cn) substep += D * solve;
  return 3 * substep + 4 * D + 4;
}

// The machine's bandwidth changes from one minute to the next on a shared host (its triad has
// gone from 22 to 39 GB/s within an hour), so each case is timed in rounds, each a block of steps
// (at least 0.4 s and one step) right after a triad on the same number of threads (best of three
// passes, as STREAM reports: the highest bandwidth, so the fraction errs low): the fraction of a
// round is the block's mean rate times the bytes over that triad, and a case's is the median of
// its rounds' (the lowest and highest round are printed and written too). With several vector
// levels, one simulation steps through every level in each round (all levels give the same bits),
// the levels' order turning from one round to the next, so that a drift of the machine falls on
// all alike. The printed GB/s is the case's mean rate times its bytes and the triad its rounds'
// median: their quotient is near, not equal to, the median of the rounds' fractions.
void throughput(bool quick, const std::vector<SimdLevel>& levels) {
  Triad triad;
  std::printf(
      "\nThroughput: Taylor-Green vortex (periodic), RK3 with 3 pressure solves per step;\n"
      "each case in %d rounds of a triad then a block of steps, the fraction of each round paired\n",
      kRounds);
  std::printf("%4s %6s %-15s %7s %12s %10s %10s %10s %9s %13s %s\n", "dim", "n", "viscous", "threads", "cell-steps/s",
              "B/cell-step", "GB/s", "triad GB/s", "of triad", "rounds min-max", "simd");
  const std::string header =
      "date,dim,n,viscous,threads,steps,wall_s,cell_steps_per_s,bytes_per_cell_step,gb_per_s,triad_gb_per_s,fraction,"
      "triad_timing,rounds,fraction_min,fraction_max,simd";
  struct Case {
    int dim, n;
    std::string viscous;
  };
  std::vector<Case> cases = {{2, 256, "explicit"},        {2, 512, "explicit"},       {2, 1024, "explicit"},
                             {2, 1024, "crank_nicolson"}, {3, 32, "explicit"},        {3, 64, "explicit"},
                             {3, 128, "explicit"},        {3, 128, "crank_nicolson"}, {3, 256, "explicit"}};
  if (quick) cases = {{2, 256, "explicit"}, {3, 64, "explicit"}};
  struct Timing {
    int64_t steps = 0;
    double wall = 0;
    std::vector<double> fractions, triads;
  };
  const size_t nl = levels.size();
  for (const Case& c : cases)
    for (int threads : {1, 2}) {
      Simulation sim(model_of(taylor_green_scene(c.dim, c.n, c.viscous)), threads);
      sim.step();  // plans, workspaces, first touch
      const double cells = std::pow(static_cast<double>(c.n), c.dim);
      const double bytes = 8 * doubles_per_cell_step(c.dim, c.viscous == "crank_nicolson");
      std::vector<Timing> at(nl);
      for (int r = 0; r < kRounds; ++r)
        for (size_t i = 0; i < nl; ++i) {
          const size_t li = (i + static_cast<size_t>(r)) % nl;
          limit_simd(levels[li]);
          Timing& t = at[li];
          t.triads.push_back(triad.bandwidth(threads, 3));
          int64_t block = 0;
          const double t0 = now_s();
          while (block < 1 || now_s() - t0 < 0.4) {
            sim.state().boundary_seen = false;
            if (!sim.step()) throw std::runtime_error("the run failed: " + sim.state().failure.message);
            ++block;
          }
          const double dt = now_s() - t0;
          t.fractions.push_back(cells * static_cast<double>(block) * bytes / dt / t.triads.back());
          t.steps += block;
          t.wall += dt;
        }
      for (size_t li = 0; li < nl; ++li) {
        const Timing& t = at[li];
        const char* name = simd_name(std::min(levels[li], simd_widest()));
        const double rate = cells * static_cast<double>(t.steps) / t.wall, bw = median(t.triads);
        const double f = median(t.fractions);
        const auto [lo, hi] = std::minmax_element(t.fractions.begin(), t.fractions.end());
        std::printf("%4d %6d %-15s %7d %12.3g %10.0f %10.2f %10.2f %8.0f%% %6.0f-%.0f%% %s\n", c.dim, c.n,
                    c.viscous.c_str(), threads, rate, bytes, rate * bytes / 1e9, bw / 1e9, 100 * f, 100 * *lo,
                    100 * *hi, name);
        append_csv(kResults + "fluid_throughput.csv", header,
                   today() + "," + std::to_string(c.dim) + "," + std::to_string(c.n) + "," + c.viscous + "," +
                       std::to_string(threads) + "," + std::to_string(t.steps) + "," + num(t.wall) + "," + num(rate) +
                       "," + num(bytes) + "," + num(rate * bytes / 1e9) + "," + num(bw / 1e9) + "," + num(f) +
                       ",paired," + std::to_string(kRounds) + "," + num(*lo) + "," + num(*hi) + "," + name);
      }
    }
  limit_simd(levels.front());
}

// One solve of the projection's Poisson equation on an n^3 box, by the fast transforms and by CG
// preconditioned by the multigrid V-cycle to a relative residual of 1e-8 (the comparison
// was with HYPRE's PFMG multigrid: 17 to 22 times), from the same right-hand side (random, zero
// mean), in a periodic box and in a walled one (Neumann on every face). Best of 5 transform
// solves and of 3 CG solves (each after an untimed one that allocates the buffers), at 1 and 2
// threads; the two solutions are compared (up to their constant) as a check that both solved the
// same problem.
void poisson(bool quick) {
  const int n = quick ? 32 : 128;
  std::printf("\nPoisson solve on %d^3 cells: fast transforms against multigrid-preconditioned CG to 1e-8\n", n);
  std::printf("%-9s %7s %10s %10s %8s %10s %10s %8s\n", "box", "threads", "fft_s", "cg_s", "cg_its", "residual",
              "max diff", "ratio");
  const std::string header = "date,n,box,threads,fft_s,cg_s,cg_iterations,cg_residual,solution_diff,ratio";
  for (const bool walls : {false, true}) {
    fluid::Grid g;
    g.dim = 3;
    g.n = {n, n, n};
    g.h = {1.0 / n, 1.0 / n, 1.0 / n};
    for (auto& axis : g.bc)
      for (fluid::Bc& bc : axis) bc.type = walls ? fluid::BcType::kNoSlip : fluid::BcType::kPeriodic;
    const auto cells = static_cast<size_t>(g.cells());
    std::vector<double> rhs(cells);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> uni(-1, 1);
    double mean = 0;
    for (double& v : rhs) mean += (v = uni(rng));
    for (double& v : rhs) v -= mean / static_cast<double>(cells);
    for (int threads : {1, 2}) {
      tbb::task_arena arena(threads);
      double fft_s = 1e30, cg_s = 1e30;
      std::vector<double> x_fft;
      linalg::Vector x_cg;
      linalg::SolveReport rep;
      arena.execute([&] {
        fluid::FastSolver fast(3, fluid::pressure_axes(g));
        for (int r = 0; r < 6; ++r) {
          x_fft = rhs;
          const double t0 = now_s();
          fast.solve(x_fft.data(), 0.0);
          if (r > 0) fft_s = std::min(fft_s, now_s() - t0);
        }
        fluid::PoissonSolverOptions opt;
        opt.cg = {1e-8, 200};
        fluid::PoissonSolver mg(g, 0.0, opt);
        const Eigen::Map<const linalg::Vector> b(rhs.data(), static_cast<Eigen::Index>(cells));
        for (int r = 0; r < 4; ++r) {
          x_cg.setZero(static_cast<Eigen::Index>(cells));
          const double t0 = now_s();
          rep = mg.solve(b, x_cg);
          if (r > 0) cg_s = std::min(cg_s, now_s() - t0);
        }
      });
      if (!rep.ok()) throw std::runtime_error("multigrid CG did not converge");
      // Both are zero-mean solutions of the singular problem: compare them after removing the means.
      double mf = 0, mc = 0, scale = 0, diff = 0;
      for (size_t i = 0; i < cells; ++i) mf += x_fft[i], mc += x_cg[static_cast<Eigen::Index>(i)];
      mf /= static_cast<double>(cells), mc /= static_cast<double>(cells);
      for (size_t i = 0; i < cells; ++i) {
        scale = std::max(scale, std::abs(x_fft[i] - mf));
        diff = std::max(diff, std::abs(x_fft[i] - mf - (x_cg[static_cast<Eigen::Index>(i)] - mc)));
      }
      const char* box = walls ? "walls" : "periodic";
      std::printf("%-9s %7d %10.4f %10.4f %8d %10.2e %10.2e %8.1f\n", box, threads, fft_s, cg_s, rep.iterations,
                  rep.residual, diff / scale, cg_s / fft_s);
      append_csv(kResults + "fluid_poisson.csv", header,
                 today() + "," + std::to_string(n) + "," + box + "," + std::to_string(threads) + "," + num(fft_s) +
                     "," + num(cg_s) + "," + std::to_string(rep.iterations) + "," + num(rep.residual) + "," +
                     num(diff / scale) + "," + num(cg_s / fft_s));
    }
  }
}

// A centreline profile (s, value) of a CSV with a header line.
std::vector<std::pair<double, double>> read_profile(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::pair<double, double>> out;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto comma = line.find(',');
    out.push_back({std::stod(line.substr(0, comma)), std::stod(line.substr(comma + 1))});
  }
  return out;
}

// Largest difference of a profile from the reference simulation's field along a centreline.
double centreline_error(const std::vector<std::pair<double, double>>& prof, const Simulation& ref,
                        const std::string& field) {
  const fluid::FluidParams& p = ref.model().params.get<fluid::FluidParams>();
  double mx = 0;
  for (const auto& [s, v] : prof) {
    const std::array<double, 3> x = field == "u" ? std::array<double, 3>{0.5, s, 0} : std::array<double, 3>{s, 0.5, 0};
    mx = std::max(mx, std::abs(v - fluid::sample(p, ref.state(), field, x)));
  }
  return mx;
}

void openfoam(bool quick) {
  // OpenFOAM first (its script appends its own rows and writes its profiles), then silt.
  const std::string script = std::string(SILT_SOURCE_DIR) + "/bench/openfoam/run_icofoam.sh";
  std::printf("\nOpenFOAM icoFoam, cavity 128 x 128, Re = 10, dt = 0.005 L/U (%s)\n", script.c_str());
  const int of_rc = std::system(("bash " + script + " > /tmp/silt_icofoam.log 2>&1").c_str());
  if (of_rc != 0) std::printf("  icoFoam did not run (see /tmp/silt_icofoam.log): silt's side only\n");
  else std::printf("%s", capture("tail -n 2 " + kResults + "fluid_openfoam.csv").c_str());
  // The reference: silt at 512^2 (256^2 with --quick) at the same time t = 2 L/U (the flow is
  // still settling there: its velocity changes by about 1e-3 per L/U), with a step ten times
  // smaller.
  const int n_ref = quick ? 256 : 512;
  Simulation ref(model_of(cavity_scene(2, n_ref, 10, "dt = 0.0005")), 2);
  while (ref.state().t < 2 - 1e-9) {
    ref.state().boundary_seen = false;
    if (!ref.step()) throw std::runtime_error(ref.state().failure.message);
  }
  const std::string header = "date,code,processes,cells,steps,wall_s,cell_steps_per_s,u_err_max,v_err_max,ref_cells";
  double silt_err_u = 0, silt_err_v = 0;
  for (int threads : {1, 2}) {
    // As icoFoam: 400 steps of 0.005 L/U (t = 2 L/U).
    Simulation sim(model_of(cavity_scene(2, 128, 10, "dt = 0.005")), threads);
    sim.step();
    const double t0 = now_s();
    for (int k = 1; k < 400; ++k) {
      sim.state().boundary_seen = k == 399;
      if (!sim.step()) throw std::runtime_error(sim.state().failure.message);
    }
    const double wall = now_s() - t0, rate = 128.0 * 128.0 * 399 / wall;
    // Its centreline profiles at the interior points s = k / 128, against the reference as icoFoam's.
    const fluid::FluidParams& p = sim.model().params.get<fluid::FluidParams>();
    std::vector<std::pair<double, double>> pu, pv;
    for (int k = 1; k < 128; ++k) {
      const double s = k / 128.0;
      pu.push_back({s, fluid::sample(p, sim.state(), "u", {0.5, s, 0})});
      pv.push_back({s, fluid::sample(p, sim.state(), "v", {s, 0.5, 0})});
    }
    const double eu = centreline_error(pu, ref, "u"), ev = centreline_error(pv, ref, "v");
    silt_err_u = eu;
    silt_err_v = ev;
    std::printf("  silt     %d thread(s): %10.3g cell-steps/s, centreline error u %.2e, v %.2e (vs silt %d^2)\n",
                threads, rate, eu, ev, n_ref);
    append_csv(kResults + "fluid_vs_openfoam.csv", header,
               today() + ",silt," + std::to_string(threads) + ",16384,399," + num(wall) + "," + num(rate) + "," +
                   num(eu) + "," + num(ev) + "," + std::to_string(n_ref * n_ref));
  }
  if (of_rc == 0) {
    const auto pu = read_profile(kResults + "openfoam_cavity_u.csv"),
               pv = read_profile(kResults + "openfoam_cavity_v.csv");
    const double eu = centreline_error(pu, ref, "u"), ev = centreline_error(pv, ref, "v");
    std::printf("  icoFoam centreline error u %.2e, v %.2e (vs silt %d^2); silt's %.2e, %.2e\n", eu, ev, n_ref,
                silt_err_u, silt_err_v);
    const std::string rows = capture("tail -n 2 " + kResults + "fluid_openfoam.csv");
    std::istringstream in(rows);
    std::string line;
    while (std::getline(in, line)) {
      std::stringstream ss(line);
      std::string procs, cells, steps, wall, rate;
      std::getline(ss, procs, ',');
      std::getline(ss, cells, ',');
      std::getline(ss, steps, ',');
      std::getline(ss, wall, ',');
      std::getline(ss, rate, ',');
      append_csv(kResults + "fluid_vs_openfoam.csv", header,
                 today() + ",icoFoam," + procs + "," + cells + "," + steps + "," + wall + "," + rate + "," + num(eu) +
                     "," + num(ev) + "," + std::to_string(n_ref * n_ref));
    }
  }
}

void frames() {
  std::printf("\nFrames\n");
  const std::string header = "date,what,cells,pixels,field_s,draw_s,png_s,total_s";
  render::Rasterizer r(2);
  auto one = [&](const std::string& what, const Model& m, const State& s, const RenderSettings& v, double cells) {
    const double t0 = now_s();
    const std::vector<GridField> f = module_grid_fields(m, s, v.field);
    const double t1 = now_s();
    const GridField* field = nullptr;
    for (const GridField& g : f)
      if (g.name == v.field) field = &g;
    const render::RenderScene rs = render::build_render_scene(m, s, v, field);
    render::Image img = r.draw(rs);
    render::compose_overlays(rs, img);
    const double t2 = now_s();
    render::write_png("/tmp/silt_fluid_" + what + ".png", img);
    const double t3 = now_s();
    std::printf("  %-28s %10.0f cells  %4d x %-4d px: fields %.3f s, draw %.3f s, PNG %.3f s\n", what.c_str(), cells,
                v.width, v.height, t1 - t0, t2 - t1, t3 - t2);
    append_csv(kResults + "fluid_frames.csv", header,
               today() + "," + what + "," + num(cells) + "," + std::to_string(v.width * v.height) + "," + num(t1 - t0) +
                   "," + num(t2 - t1) + "," + num(t3 - t2) + "," + num(t3 - t0));
  };
  {
    Simulation sim(model_of(cavity_scene(2, 1024, 1000, "cfl = 0.5")), 2);
    for (int k = 0; k < 200; ++k) sim.step();
    RenderSettings v = sim.model().render;
    v.width = v.height = 1024;
    v.draw = {"field", "colorbar", "time", "scalebar"};
    v.field = "vorticity";
    one("cavity_2d_vorticity", sim.model(), sim.state(), v, 1024.0 * 1024);
  }
  {
    Simulation sim(model_of(cavity_scene(3, 128, 100, "cfl = 0.5")), 2);
    for (int k = 0; k < 50; ++k) sim.step();
    RenderSettings v = sim.model().render;
    v.width = v.height = 1024;
    v.draw = {"field", "colorbar", "time", "scalebar"};
    v.field = "vorticity";
    v.slice_normal[0] = 0, v.slice_normal[1] = 0, v.slice_normal[2] = 1;
    v.slice_position = 0.5;
    v.slice_component = "z";
    v.elevation = 89;
    v.azimuth = -90;
    one("cavity_3d_slice_vorticity_z", sim.model(), sim.state(), v, 128.0 * 128 * 128);
  }
}

}  // namespace

int main(int argc, char** argv) {
  return guarded_main([&] {
    std::string only;
    bool quick = false;
    std::vector<SimdLevel> levels = {simd_level()};
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--only" && i + 1 < argc) only = argv[++i];
      else if (a == "--quick") quick = true;
      else if (a == "--simd" && i + 1 < argc) levels = simd_levels(argv[++i]);
      else
        throw std::invalid_argument(
            "usage: fluid [--only cavity|throughput|openfoam|frames|poisson|viscous] [--quick] [--simd "
            "baseline,avx2,avx512]");
    }
    check_only(only, {"throughput", "cavity", "openfoam", "frames", "poisson", "viscous"});
    std::printf("silt fluid benchmark, %s, %s\n", cpu_model().c_str(), today().c_str());
    limit_simd(levels.front());
    if (only.empty() || only == "throughput") throughput(quick, levels);
    if (only.empty() || only == "cavity") cavity(quick);
    if (only.empty() || only == "openfoam") openfoam(quick);
    if (only.empty() || only == "frames") frames();
    if (only.empty() || only == "poisson") poisson(quick);
    if (only.empty() || only == "viscous") viscous_schemes();
    return 0;
  });
}
