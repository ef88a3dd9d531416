// The small silo of scenes/silo.toml: how the weight of poured grains is shared between the
// floor and the side walls, against Janssen's column with fully mobilised wall friction.
//
//   build/bench/silo [--threads N] [--seed S]
//
// Runs the scene for its time and prints, every 0.1 s, the floor's load and the side walls'
// vertical force relative to the weight of the grains; at the end the column height, its packing
// fraction, and Janssen's apparent mass (lambda/h)(1 - exp(-h/lambda)), lambda = S/(P K mu_w),
// for K = 0.4 to 0.6 (Izard 2014 eq. 2.11 with P_m the perimeter). Appends the final state to
// bench/results/silo.csv.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "bench_util.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

int run(int argc, char** argv) {
  int threads = 2;
  long seed = 2014;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seed")) seed = std::atol(argv[i + 1]);
  }
  const std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/silo.toml";
  Model model = compile(load_scene_file(scene, {parse_override("scene.seed=" + std::to_string(seed))}));
  const double g = model.gravity.norm();
  double weight = 0, volume = 0;
  for (int64_t i = 0; i < model.n_grains; ++i) {
    weight += model.init.mass[i] * g;
    volume += grain_volume(3, model.init.radius[i]);
  }
  const double side = model.walls[1].point.x() - model.walls[0].point.x();  // square tube, walls 0-3
  const double mu_w = model.walls[0].friction;
  const Observer obs(model, {"t", "wall[4].fz", "wall[0].fz", "wall[1].fz", "wall[2].fz", "wall[3].fz", "ke"});
  Simulation sim(std::move(model), threads);
  const Model& m = sim.model();
  std::printf("silo: %lld grains, weight %.4f N, tube %.3g m wide, wall friction %.2f\n",
              static_cast<long long>(m.n_grains), weight, side, mu_w);
  std::printf("%8s %12s %12s %12s\n", "t [s]", "floor / W", "sides / W", "ke [J]");
  RunOptions opt;
  opt.steps = m.run_steps;
  double floor = 0, sides = 0;
  const int64_t every = std::max<int64_t>(1, static_cast<int64_t>(std::llround(0.1 / m.dt)));
  opt.hooks.push_back({every, [&](const State& s) {
                         const std::vector<double> v = obs.sample(m, s);
                         floor = -v[1];
                         sides = -(v[2] + v[3] + v[4] + v[5]);
                         std::printf("%8.3f %12.4f %12.4f %12.3g\n", v[0], floor / weight, sides / weight, v[6]);
                       }});
  const double t0 = bench::now_s();
  const RunReport rep = sim.run(opt);
  if (rep.end == RunEnd::kFailed) {
    std::fprintf(stderr, "silo failed: %s\n", sim.state().failure.message.c_str());
    return 3;
  }
  const State& s = sim.state();
  double top = 0;
  for (int64_t i = 0; i < s.n; ++i) top = std::max(top, s.particle_x[3 * i + 2] + s.particle_r[i]);
  const double area = side * side, perimeter = 4 * side, phi = volume / (area * top);
  std::printf("\ncolumn height h = %.4f m (h / width = %.2f), packing fraction %.3f, %.0f s\n", top, top / side, phi,
              bench::now_s() - t0);
  std::printf("floor carries %.4f of the weight, side walls %.4f (positive: they hold grains up)\n", floor / weight,
              sides / weight);
  std::ostringstream row;
  row << bench::today() << "," << seed << "," << m.n_grains << "," << s.t << "," << weight << "," << floor / weight
      << "," << sides / weight << "," << top << "," << phi;
  for (double K : {0.4, 0.5, 0.6}) {
    const double lambda = area / (perimeter * K * mu_w);
    const double janssen = lambda / top * (1 - std::exp(-top / lambda));
    std::printf("Janssen, fully mobilised friction, K = %.1f: lambda = %.3f m, floor / W = %.3f\n", K, lambda, janssen);
    row << "," << janssen;
  }
  bench::append_csv(std::string(SILT_SOURCE_DIR) + "/bench/results/silo.csv",
                    "date,seed,n_grains,t,weight_N,floor_over_weight,sides_over_weight,height_m,phi,janssen_K0.4,"
                    "janssen_K0.5,janssen_K0.6",
                    row.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
