// Lees-Edwards shear of frictional disks in silt and in LAMMPS (Debian package `lammps`: a
// triclinic box deformed by fix deform xy erate with remap v, pair gran/hooke/history,
// fix nve/sphere disc), from the same prepared packing, at the same fixed volume and shear rate:
// an independent check of the sheared boundaries, the frictional contacts and the stress.
//
//   build/bench/shear2d_vs_lammps [--strain G] [--friction MU] [--threads N]
//
// The packing is procedure O of scenes/shear2d_dry.toml (896 disks, k_N/P = 1e4). Both codes
// then use LAMMPS's gran/hooke law (silt's contact.model = "hooke"): k_n = 1e4, k_t = k_n/2,
// dashpot m* gamma_n with gamma_n = 2 zeta sqrt(k_n / m*) for the mean pair (zeta = 0.98), no
// tangential dashpot, Coulomb bound mu |F_n|. Disks have mass pi r^2 and inertia m r^2 / 2 in
// both. The shear rate is that of I = 1e-2 at P = 1. Prints mu = <|sigma_xy|> / <sigma_yy> and
// the block-averaged mean of |sigma_xy| / sigma_yy over the strains after 1, for each code.
// At fixed volume the pressure of a packing this close to jamming fluctuates by an order of
// magnitude over a unit of strain, so the pressures are compared only roughly.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "bench_util.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

// The samples of one code and what is reported of them: <tau>/<sigma_yy>, the block-averaged
// <tau/sigma_yy> and <sigma_yy>, and the wall time of the run.
struct Series {
  std::vector<double> tau, syy;
  double wall = 0;
  void add(double t, double y) {
    tau.push_back(std::abs(t));
    syy.push_back(y);
  }
  double ratio_of_means() const {
    double st = 0, sy = 0;
    for (size_t k = 0; k < tau.size(); ++k) st += tau[k], sy += syy[k];
    return st / sy;
  }
  BlockAverage mean_ratio() const {
    std::vector<double> ratio;
    for (size_t k = 0; k < tau.size(); ++k) ratio.push_back(syy[k] > 0 ? tau[k] / syy[k] : 0);
    return block_average(ratio);
  }
  void print(const char* who) const {
    const BlockAverage r = mean_ratio(), p = block_average(syy);
    std::printf("%-8s %-10zu %-16.4f %-20s %-18s %.1f\n", who, tau.size(), ratio_of_means(),
                (std::to_string(r.mean).substr(0, 6) + " +- " + std::to_string(r.err).substr(0, 6)).c_str(),
                (std::to_string(p.mean).substr(0, 6) + " +- " + std::to_string(p.err).substr(0, 6)).c_str(), wall);
  }
  // Fields of the CSV row: ratio of means, mean ratio and its error, <syy> and its error, wall time.
  std::string csv() const {
    const BlockAverage r = mean_ratio(), p = block_average(syy);
    std::ostringstream o;
    o << ratio_of_means() << "," << r.mean << "," << r.err << "," << p.mean << "," << p.err << "," << wall;
    return o.str();
  }
};

int run(int argc, char** argv) {
  double strain = 8, mu = 0.3;
  int threads = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--strain")) strain = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--friction")) mu = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
  }
  const std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/shear2d_dry.toml";
  const Model dry = compile(load_scene_file(scene));
  PreparationReport prep;
  const State packed = prepare_packing(dry, threads, &prep);
  const double lx = packed.box.len[0], ly = packed.box.len[1];
  const double gd = dry.shear.rate, dt = dry.dt, kn = 1e4, zeta = 0.98;
  const double gamma_n = 2 * zeta * std::sqrt(kn / (0.5 * dry.m_mean));
  const int64_t steps = static_cast<int64_t>(strain / (gd * dt));
  const int64_t every = 1000;
  std::printf(
      "packing: %lld disks, Phi = %.4f, box %.4f x %.4f; gammadot = %.6g, dt = %.6g, %lld steps, gamma_n = %.4g\n",
      static_cast<long long>(dry.n_grains), measure(dry, packed).phi, lx, ly, gd, dt, static_cast<long long>(steps),
      gamma_n);

  // silt: the same grains at fixed volume, hooke law, imposed shear rate.
  std::ostringstream toml;
  toml.precision(17);
  toml << "[scene]\ndimension = 2\nseed = 1\n[domain]\nlo = [0.0, 0.0]\nhi = [39.5, 39.5]\nperiodic = [true, true]\n"
       << "[shear]\nrate = " << gd << "\n[contact]\nmodel = \"hooke\"\nk_n = " << kn << "\ngamma_n = " << gamma_n
       << "\nfriction = " << mu
       << "\nkt_over_kn = 0.5\n[[grains]]\nname = \"disks\"\ncount = 896\nradius_min = 0.35\nradius_max = 0.5\n"
       << "density = 1.0\nplacement = \"random\"\n[run]\ndt = " << dt << "\n";
  Simulation sim(compile(parse_scene(toml.str(), "shear2d_fixed_volume.toml")), threads);
  sim.restore(packed);
  const Model& m = sim.model();
  Series silt_series;
  RunOptions opt;
  opt.steps = steps;
  opt.hooks.push_back({every, [&](const State& s) {
                         if (s.shear_strain < 1) return;
                         const Measurements q = measure(m, s, measure_part::kStress);
                         silt_series.add(q.stress[0][1], q.stress[1][1]);
                       }});
  silt_series.wall = sim.run(opt).wall_s;

  // LAMMPS: the same packing, box and law.
  const std::string data = "shear2d_vs_lammps.data", input = "shear2d_vs_lammps.in";
  {
    std::ofstream d(data);
    d.precision(17);
    d << "silt prepared packing\n\n"
      << packed.n << " atoms\n1 atom types\n\n0 " << lx << " xlo xhi\n0 " << ly
      << " ylo yhi\n-0.5 0.5 zlo zhi\n0 0 0 xy xz yz\n\nAtoms # sphere\n\n";
    for (int64_t i = 0; i < packed.n; ++i) {
      const double r = packed.particle_r[i];
      // LAMMPS gives a sphere's mass 4/3 pi r^3 rho: rho = 3 / (4 r) makes it pi r^2.
      d << i + 1 << " 1 " << 2 * r << " " << 3.0 / (4.0 * r) << " " << packed.particle_x[2 * i] << " "
        << packed.particle_x[2 * i + 1] << " 0\n";
    }
    std::ofstream in(input);
    in.precision(17);
    in << "dimension 2\nunits lj\natom_style sphere\nboundary p p p\nnewton off\ncomm_modify vel yes\nread_data "
       << data << "\npair_style gran/hooke/history " << kn << " " << 0.5 * kn << " " << gamma_n << " 0 " << mu
       << " 0\npair_coeff * *\nneighbor 0.1 bin\nneigh_modify every 1 delay 0\ntimestep " << dt
       << "\nvelocity all ramp vx 0.0 " << gd * ly << " y 0 " << ly << " sum no units box\n"
       << "fix 1 all nve/sphere disc\nfix 2 all enforce2d\nfix 3 all deform 1 xy erate " << gd << " remap v flip yes\n"
       << "compute p all pressure NULL virial\nthermo_style custom step time c_p[2] c_p[4]\nthermo_modify norm no\n"
       << "thermo " << every << "\nrun " << steps << "\n";
  }
  const double t0 = bench::now_s();
  const std::string out = bench::capture("OMP_NUM_THREADS=1 lmp -in " + input + " -log none 2>&1");
  Series lammps_series;
  lammps_series.wall = bench::now_s() - t0;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream f(line);
    double step, time, pyy, pxy;
    std::string extra;
    if (!(f >> step >> time >> pyy >> pxy) || (f >> extra)) continue;
    if (time * gd >= 1) lammps_series.add(pxy, pyy);
  }
  if (lammps_series.tau.empty()) {
    std::fprintf(stderr, "LAMMPS did not run (is the `lammps` package installed?):\n%s\n", out.c_str());
    return 1;
  }
  std::printf("\n%-8s %-10s %-16s %-20s %-18s %s\n", "code", "samples", "<tau>/<syy>", "<tau/syy> +- err",
              "<syy> +- err", "wall s");
  silt_series.print("silt");
  lammps_series.print("LAMMPS");
  // Per code: <tau>/<syy>, <tau/syy> and its error, <syy> and its error, wall time [s]
  // (silt on --threads threads, LAMMPS on one process); then the packing's Phi.
  std::ostringstream row;
  row << bench::today() << "," << mu << "," << strain << "," << silt_series.csv() << "," << lammps_series.csv() << ","
      << threads << "," << measure(dry, packed).phi;
  bench::append_csv(
      std::string(SILT_SOURCE_DIR) + "/bench/results/shear2d_vs_lammps.csv",
      "date,friction,strain,mu_silt,mu_ratio_silt,mu_ratio_err_silt,syy_silt,syy_err_silt,wall_s_silt,"
      "mu_lammps,mu_ratio_lammps,mu_ratio_err_lammps,syy_lammps,syy_err_lammps,wall_s_lammps,threads_silt,"
      "phi",
      row.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
