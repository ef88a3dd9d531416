// silt's lubricated paste against LAMMPS's pair lubricateU (Debian package `lammps`, COLLOID
// package) on one system: scenes/paste_3d_shear.toml, 4,096 monodisperse spheres of radius 1 at
// Phi = 0.45 (silt's prepared packing, written as a LAMMPS data file), viscosity 1, sheared at
// gammadot = 0.01 (lubricateU's gdot equals the fix deform rate: otherwise it solves for nothing).
// Both solve every velocity from the lubrication resistance each step: silt with CG preconditioned
// by a Cholesky factor of an earlier matrix (its lubrication.h_min_over_a as the roughness
// cutoff), LAMMPS with plain CG on Ball-Melrose lubrication (cutinner the same gap). Grain-steps
// per second of each, on one process / thread and on two (LAMMPS two MPI ranks, silt two
// threads); and how each one's cost grows as the gaps close (silt: h_min/a; LAMMPS: cutinner) and
// as the packing tightens (Phi: the same dry compression stopped at each, up to touching grains).
//
//   build/bench/paste_vs_lammps [--steps N] [--lammps-steps N] [--no-lammps] [--gaps X,Y,...]
//                               [--phis P,Q,...] [--lammps-down-to X] [--lammps-limit S]
//                               [--set KEY=VALUE ...]
//
// --gaps: the values of h_min/a (default 1e-2,1e-3,1e-4,1e-6,1e-8); LAMMPS runs those down to
// --lammps-down-to (default 1e-4: its plain CG's cost grows as the gaps close, and at 1e-6 it
// did not finish a step in 20 minutes). --phis: the packing fractions the grains are compressed
// to (prepare.phi, default the scene's 0.45; 0.60 has 5.1 contacts a grain). --set: a scene key
// for silt's runs, as `silt run --set` (e.g. lubrication.tolerance=1e-4: LAMMPS's CG stops at
// 1e-4, silt's at the scene's 1e-8; lubrication.stokes_drag=true: lubricateU's resistance holds
// each grain's one-body drag, 6 pi mu a on its velocity and 8 pi mu a^3 on its rotation relative
// to the liquid's, which silt's scene, the thesis' model, leaves out; the drag is that key's).
// --lammps-limit: seconds after which a LAMMPS run is stopped (default 1200); its row then says
// so, with a rate of 0.
//
// Appends to bench/results/paste_vs_lammps.csv. Reproduce LAMMPS alone: the input and data it
// runs are left in /tmp/silt_paste_lammps/.
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "paste/solve.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

const std::string kDir = "/tmp/silt_paste_lammps";
const std::string kCsv = std::string(SILT_SOURCE_DIR) + "/bench/results/paste_vs_lammps.csv";
const std::string kHeader =
    "date,code,case,h_min_over_a,threads,grains,steps,wall_s,grain_steps_per_s,iters_mean,"
    "refactorisations,note";

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.12g", x);
  return b;
}

// The packing as a LAMMPS data file (atom_style sphere: id type diameter density x y z), in a
// triclinic box of zero tilt that fix deform shears.
void write_data(const State& s, const std::string& path) {
  std::ofstream o(path);
  o.precision(17);
  o << "silt paste_3d_shear packing\n\n" << s.n << " atoms\n1 atom types\n\n";
  const char* ax[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a)
    o << s.box.lo[a] << ' ' << s.box.lo[a] + s.box.len[a] << ' ' << ax[a] << "lo " << ax[a] << "hi\n";
  o << "0 0 0 xy xz yz\n\nAtoms # sphere\n\n";
  for (int64_t i = 0; i < s.n; ++i)
    o << i + 1 << " 1 " << 2 * s.particle_r[i] << " 1 " << s.particle_x[3 * i] << ' ' << s.particle_x[3 * i + 1] << ' '
      << s.particle_x[3 * i + 2] << '\n';
}

void write_input(const std::string& path, double cutinner, double cutoff, double gdot, int steps, double dt) {
  std::ofstream o(path);
  o << "units lj\ndimension 3\nboundary p p p\natom_style sphere\nnewton off\ncomm_modify vel yes\n"
    << "read_data " << kDir << "/data.paste\n"
    << "pair_style lubricateU 1.0 1 " << num(cutinner) << ' ' << num(cutoff) << ' ' << num(gdot) << " 1 0\n"
    << "pair_coeff * *\nneighbor 0.3 bin\nneigh_modify every 1 delay 0\n"
    << "fix 1 all nve/noforce\nfix 2 all deform 1 xy erate " << num(gdot) << " remap v\n"
    << "timestep " << num(dt) << "\nthermo " << steps << "\nrun " << steps << "\n";
}

struct Lammps {
  double rate = 0;
  bool timed_out = false;  // no result within the time limit
  std::string error;
};

// One process, or two MPI ranks (the two cores, as silt's two threads).
Lammps run_lammps(double cutinner, int steps, double dt, double limit_s, int ranks) {
  write_input(kDir + "/in.paste", cutinner, 3.0, 0.01, steps, dt);
  const double t0 = bench::now_s();
  const std::string out = bench::capture("cd " + kDir + " && OMP_NUM_THREADS=1 timeout " + num(limit_s) + " " +
                                         bench::lammps_launch(ranks) + " -in in.paste -log none 2>&1");
  Lammps l;
  const std::regex loop(R"(Loop time of ([0-9.eE+-]+) on )" + std::to_string(ranks) +
                        R"( procs for (\d+) steps with (\d+) atoms)");
  std::smatch m;
  if (std::regex_search(out, m, loop)) {
    const double t = std::stod(m[1]);
    l.rate = std::stod(m[3]) * std::stod(m[2]) / t;
  } else {
    l.timed_out = bench::now_s() - t0 >= limit_s;
    l.error = out.size() > 600 ? out.substr(out.size() - 600) : out;
  }
  return l;
}

struct Silt {
  double rate = 0, iters = 0, refactor = 0;
};

Silt run_silt(const Model& m, const State& packing, int threads, int steps) {
  Simulation sim(m, threads);
  sim.restore(packing);
  RunOptions opt;
  opt.steps = 1;  // the first solve (and factorisation) from the packing, not timed
  sim.run(opt);
  const auto& v0 = sim.state().module_field(paste::paste_fields().solver);
  const double solves0 = v0[paste::kSolves], iters0 = v0[paste::kIterationsTotal], ref0 = v0[paste::kRefactorizations];
  opt.steps = steps;
  const RunReport rep = sim.run(opt);
  const auto& v = sim.state().module_field(paste::paste_fields().solver);
  Silt s;
  s.rate = static_cast<double>(m.n_grains) * static_cast<double>(rep.steps_done) / rep.wall_s;
  s.iters = (v[paste::kIterationsTotal] - iters0) / std::max(1.0, v[paste::kSolves] - solves0);
  s.refactor = v[paste::kRefactorizations] - ref0;
  return s;
}

struct Options {
  int steps = 30, lmp_steps = 30;
  bool lammps = true;
  std::vector<double> gaps{1e-2, 1e-3, 1e-4, 1e-6, 1e-8};
  std::vector<double> phis;  // the scene's by default
  double lammps_down_to = 1e-4;
  std::vector<Override> sets;  // silt's scene keys
  std::string set_note;        // and how the rows name them
  double lammps_limit = 1200;
};

void row(const Model& base, const std::string& code, const std::string& name, double h, int threads, int n_steps,
         double rate, double iters, double refactor, const std::string& note) {
  std::printf("%-8s %-36s %8d %14.4g %8.1f %8.0f  %s\n", code.c_str(), name.c_str(), threads, rate, iters, refactor,
              note.c_str());
  std::fflush(stdout);
  std::ostringstream o;
  o << bench::today() << ',' << code << ',' << name << ',' << num(h) << ',' << threads << ',' << base.n_grains << ','
    << n_steps << ',' << num(rate > 0 ? base.n_grains * n_steps / rate : 0) << ',' << num(rate) << ',' << num(iters)
    << ',' << num(refactor) << ',' << note;
  bench::append_csv(kCsv, kHeader, o.str());
}

// Both codes at every gap on one packing. The roughness cutoff of each: silt's h_min = x a (a = 2),
// LAMMPS's cutinner = 2 + x a.
void compare_at(const Options& o, const std::string& scene, const std::vector<Override>& packing_sets, double phi) {
  const Model base = compile(load_scene_file(scene, packing_sets));
  const State packing = prepare_packing(base, 2);
  write_data(packing, kDir + "/data.paste");
  std::printf("paste_3d_shear: %lld spheres, Phi %.4f, on %s\n", static_cast<long long>(base.n_grains),
              measure(base, packing).phi, bench::cpu_model().c_str());
  const std::string at = " phi=" + num(phi);
  for (double x : o.gaps) {
    std::vector<Override> over = packing_sets;
    over.push_back(parse_override("lubrication.h_min_over_a=" + num(x)));
    const Model m = compile(load_scene_file(scene, over));
    for (int threads : {1, 2}) {
      const Silt s = run_silt(m, packing, threads, o.steps);
      // The note names the solver: the default, unless a --set chose another.
      const bool chosen = o.set_note.find("lubrication.solver=") != std::string::npos;
      row(base, "silt", "h_min/a=" + num(x) + at, x, threads, o.steps, s.rate, s.iters, s.refactor,
          chosen ? o.set_note.substr(1) : "factor_pcg" + o.set_note);
    }
    for (int ranks : {1, 2}) {
      if (!o.lammps || x < o.lammps_down_to) break;
      const Lammps l = run_lammps(2 + 2 * x, o.lmp_steps, 1e-3, o.lammps_limit, ranks);
      const std::string name = "cutinner=" + num(2 + 2 * x) + at;
      if (l.rate > 0) row(base, "lammps", name, x, ranks, o.lmp_steps, l.rate, 0, 0, "lubricateU");
      else if (l.timed_out)
        row(base, "lammps", name, x, ranks, o.lmp_steps, 0, 0, 0,
            "lubricateU stopped after " + num(o.lammps_limit) + " s; its " + std::to_string(o.lmp_steps) +
                " step(s) not done");
      else
        std::printf("LAMMPS did not run (cutinner %s, %d ranks):\n%s\n", num(2 + 2 * x).c_str(), ranks,
                    l.error.c_str());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] {
    Options o;
    for (int i = 1; i < argc; ++i) {
      if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) o.steps = std::atoi(argv[++i]);
      else if (!std::strcmp(argv[i], "--lammps-steps") && i + 1 < argc) o.lmp_steps = std::atoi(argv[++i]);
      else if (!std::strcmp(argv[i], "--no-lammps")) o.lammps = false;
      else if (!std::strcmp(argv[i], "--gaps") && i + 1 < argc) o.gaps = bench::parse_list(argv[++i]);
      else if (!std::strcmp(argv[i], "--phis") && i + 1 < argc) o.phis = bench::parse_list(argv[++i]);
      else if (!std::strcmp(argv[i], "--lammps-down-to") && i + 1 < argc) o.lammps_down_to = std::atof(argv[++i]);
      else if (!std::strcmp(argv[i], "--set") && i + 1 < argc) {
        o.sets.push_back(parse_override(argv[++i]));
        o.set_note += std::string(" ") + argv[i];
      } else if (!std::strcmp(argv[i], "--lammps-limit") && i + 1 < argc) o.lammps_limit = std::atof(argv[++i]);
      else throw std::invalid_argument(std::string("unknown option ") + argv[i]);
    }
    ::mkdir(kDir.c_str(), 0755);
    const std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/paste_3d_shear.toml";
    if (o.phis.empty()) o.phis.push_back(compile(load_scene_file(scene)).prepare.phi);
    std::printf("%-8s %-36s %8s %14s %8s %8s\n", "code", "case", "threads", "grain-steps/s", "iters", "refact");
    for (double phi : o.phis) {
      std::vector<Override> packing_sets{parse_override("prepare.phi=" + num(phi))};
      packing_sets.insert(packing_sets.end(), o.sets.begin(), o.sets.end());
      compare_at(o, scene, packing_sets, phi);
    }
    return 0;
  });
}
