// Dry 2D packings of Peyneau (2009) sec. 2.3.2 (scenes/pack_2d.toml): N = 224 disks, diameters
// uniform in [0.7a, a], k_N/P = 1e4, isotropic compression at P to a static state.
//
//   build/bench/pack_2d [--seeds N] [--threads N] [--mass-factors 0.01,1,100]
//
// For mu = 0.3 and mu = 0 (and each box mass M = factor * N m), runs N seeds to equilibrium and
// prints Phi with mean, standard deviation and error of the mean, next to the thesis' values
// (0.802 +- 0.010 and 0.836 +- 0.002 over 5 configurations), and the coordination: z* = z/(1 - p0)
// (the thesis' skeleton, without the grains of no contact, sec. 2.3.1), the fraction p0 of those,
// and z_mech (grains with fewer than 2 contacts with friction, 3 without, removed repeatedly).
// Appends to bench/results/pack_2d.csv.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <vector>

#include "bench_util.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

int run(int argc, char** argv) {
  int seeds = 5, threads = 2;
  std::vector<double> factors = {1.0};
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--seeds")) seeds = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--mass-factors")) factors = bench::parse_list(argv[i + 1]);
  }
  const std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/pack_2d.toml";
  std::printf("%-6s %-8s %-22s %-16s %-16s %-7s %-8s %-10s %-8s %s\n", "mu", "M/(Nm)", "Phi mean +- sd (err)",
              "z* mean +- sd", "z_mech +- sd", "p0", "static", "steps", "wall s", "Peyneau Phi");
  for (double mu : {0.3, 0.0}) {
    for (double factor : factors) {
      std::vector<double> phi, zs, zm, p0;
      int n_static = 0;
      double steps = 0, wall = 0;
      for (int seed = 1; seed <= seeds; ++seed) {
        std::ostringstream f, sd, mf;
        f << "contact.friction=" << mu;
        sd << "scene.seed=" << seed;
        mf << "box.mass_factor=" << factor;
        Model m = compile(
            load_scene_file(scene, {parse_override(f.str()), parse_override(sd.str()), parse_override(mf.str())}));
        Simulation sim(std::move(m), threads);
        RunOptions opt;
        opt.steps = sim.model().run_steps;
        opt.stop_when_static = true;
        const RunReport r = sim.run(opt);
        n_static += r.end == RunEnd::kStatic;
        const Measurements meas = measure(sim.model(), sim.state());
        phi.push_back(meas.phi);
        zs.push_back(meas.z_star);
        zm.push_back(meas.z_mech);
        p0.push_back(meas.p0);
        steps += static_cast<double>(r.steps_done) / seeds;
        wall += r.wall_s;
      }
      auto stats = [](const std::vector<double>& v) {
        double mean = 0, var = 0;
        for (double x : v) mean += x / v.size();
        for (double x : v) var += (x - mean) * (x - mean) / std::max<size_t>(1, v.size() - 1);
        return std::pair{mean, std::sqrt(var)};
      };
      const auto [pm, ps] = stats(phi);
      const auto [zsm, zssd] = stats(zs);
      const auto [zmm, zmsd] = stats(zm);
      const double p0m = stats(p0).first;
      char pbuf[64], zbuf[64], mbuf[64];
      std::snprintf(pbuf, sizeof pbuf, "%.4f +- %.4f (%.4f)", pm, ps, ps / std::sqrt(phi.size()));
      std::snprintf(zbuf, sizeof zbuf, "%.3f +- %.3f", zsm, zssd);
      std::snprintf(mbuf, sizeof mbuf, "%.3f +- %.3f", zmm, zmsd);
      std::printf("%-6.2f %-8.3g %-22s %-16s %-16s %-7.4f %d/%-6d %-10.0f %-8.1f %s\n", mu, factor, pbuf, zbuf, mbuf,
                  p0m, n_static, seeds, steps, wall, mu > 0 ? "0.802 +- 0.010" : "0.836 +- 0.002");
      std::ostringstream row;
      row << bench::today() << "," << mu << "," << factor << "," << seeds << "," << pm << "," << ps << "," << zsm << ","
          << zssd << "," << n_static << "," << steps << "," << wall << "," << (mu > 0 ? 0.802 : 0.836) << ","
          << (mu > 0 ? 0.010 : 0.002) << "," << zmm << "," << zmsd << "," << p0m;
      bench::append_csv(std::string(SILT_SOURCE_DIR) + "/bench/results/pack_2d.csv",
                        "date,mu,mass_factor,seeds,phi_mean,phi_sd,zstar_mean,zstar_sd,n_static,mean_steps,wall_s,"
                        "peyneau_phi,peyneau_sd,zmech_mean,zmech_sd,p0_mean",
                        row.str());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
