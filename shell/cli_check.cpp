// `silt check`: validate a scene, print the compiled model, its step graph and memory.
#include <iostream>

#include "shell/commands.hpp"
#include "shell/scene_loading.hpp"
#include "silt/simulation.hpp"

namespace silt::cli {

int check_command(const CheckArgs& a) {
  int code = 0;
  auto loaded = load_model(a.scene, a.sets, code);
  if (!loaded) return code;
  std::cout << describe(*loaded);
  Simulation sim(std::move(*loaded), a.threads);
  sim.prepare();
  const State& s = sim.state();
  std::cout << "step graph\n" << sim.describe_graph();
  const double bytes = static_cast<double>(state_bytes(s));
  std::printf("memory       %.3g MiB for the state (%.0f bytes per grain), %lld neighbour pairs\n", bytes / (1 << 20),
              bytes / std::max<int64_t>(1, s.n), static_cast<long long>(s.n_pairs()));
  std::cout << "ok\n";
  return 0;
}

}  // namespace silt::cli
