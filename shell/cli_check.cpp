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
  const double state = static_cast<double>(state_bytes(s)), all = static_cast<double>(sim.memory_bytes());
  if (s.n > 0)
    std::printf(
        "memory       %.3g MiB estimated before the start; %.3g MiB held now: %.3g MiB for the state (%.0f bytes "
        "per grain), the rest for the restart point, cell lists and pair schedule; %lld neighbour pairs\n",
        estimated_memory_bytes(sim.model()) / (1 << 20), all / (1 << 20), state / (1 << 20),
        state / std::max<int64_t>(1, s.n), static_cast<long long>(s.n_pairs()));
  else
    std::printf(
        "memory       %.3g MiB estimated before the start (the grid's fields and the step's workspaces); %.3g "
        "MiB held now, %.3g MiB of it for the state\n",
        estimated_memory_bytes(sim.model()) / (1 << 20), all / (1 << 20), state / (1 << 20));
  std::cout << "ok\n";
  return 0;
}

}  // namespace silt::cli
