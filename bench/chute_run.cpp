// The whole chute run, as the README's main job runs it, against LAMMPS on the same system: silt
// `run scenes/chute.toml` (33,000 steps, its stats and summary; no frames, which LAMMPS does not
// draw) on 1 and 2 threads, and `lmp -in ../shared/bench/lammps_chute.in -var settle 30000 -var
// steps 3000` (Debian's `lammps`) on 1 process and 2 MPI ranks. Optionally a second silt binary
// (--baseline, a build of an earlier commit) on the same runs, to compare two versions side by
// side. The runs are interleaved, in a rotating order, --repeat times: the machine's speed drifts
// over minutes, and medians of interleaved runs are what can be compared.
//
//   build/bench/chute_run [--silt PATH] [--baseline PATH] [--repeat N] [--no-lammps] [--steps N]
//
// After each round, a loop with the memory traffic of silt's kick over the chute's 17,600 grains
// (machine_reference.hpp, 30,000 sweeps) on 1 and 2 threads: what this machine's memory gives a
// grain pass from the second core at that moment.
//
// Prints the wall time of every run and the medians with their ratios; appends one row per run
// to bench/results/chute_run.csv (the reference as program "stream-reference", its sweeps in the
// steps column).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "machine_reference.hpp"

using namespace silt;
using silt::bench::median;

namespace {

struct Job {
  std::string program;  // silt, silt-baseline, lammps
  int cores;            // threads or ranks
  std::string command;
};

int run(int argc, char** argv) {
  const std::string src = SILT_SOURCE_DIR;
  std::string silt = src + "/build/silt", baseline, steps = "33000";
  int repeat = 3;
  bool lammps = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--silt") silt = value();
    else if (a == "--baseline") baseline = value();
    else if (a == "--repeat") repeat = std::max(1, std::atoi(value().c_str()));
    else if (a == "--steps") steps = value();
    else if (a == "--no-lammps") lammps = false;
    else throw std::runtime_error("unknown option " + a);
  }
  const std::string scene = src + "/scenes/chute.toml";
  const std::string out = "/tmp/silt_chute_run";
  auto silt_job = [&](const std::string& name, const std::string& bin, int t) {
    return Job{name, t,
               bin + " run " + scene + " --quiet --steps " + steps + " --threads " + std::to_string(t) + " --stats " +
                   out + ".csv --summary " + out + ".json > /dev/null"};
  };
  std::vector<Job> jobs = {silt_job("silt", silt, 1), silt_job("silt", silt, 2)};
  if (!baseline.empty()) {
    jobs.push_back(silt_job("silt-baseline", baseline, 1));
    jobs.push_back(silt_job("silt-baseline", baseline, 2));
  }
  if (lammps) {
    const std::string in = src + "/../shared/bench/lammps_chute.in";
    const std::string settle = std::to_string(std::max(0, std::atoi(steps.c_str()) - 3000));
    const std::string args = " -in " + in + " -var settle " + settle + " -var steps 3000 -log none -screen none";
    for (int ranks : {1, 2}) jobs.push_back({"lammps", ranks, bench::lammps_launch(ranks) + args});
  }
  std::map<std::pair<std::string, int>, std::vector<double>> times;
  const std::string date = bench::today(), cpu = bench::cpu_model();
  constexpr int64_t kStreamGrains = 17600, kStreamSweeps = 30000;
  bench::StreamLoop stream(kStreamGrains);
  for (int r = 0; r < repeat; ++r) {
    for (size_t k = 0; k < jobs.size(); ++k) {
      const Job& j = jobs[(k + r) % jobs.size()];  // a rotating order
      const double t0 = bench::now_s();
      const int rc = std::system(j.command.c_str());
      const double wall = bench::now_s() - t0;
      if (rc != 0) throw std::runtime_error("failed (" + std::to_string(rc) + "): " + j.command);
      times[{j.program, j.cores}].push_back(wall);
      std::printf("round %d  %-14s %d core(s)  %7.2f s\n", r + 1, j.program.c_str(), j.cores, wall);
      std::fflush(stdout);
      bench::append_csv(src + "/bench/results/chute_run.csv", "date,cpu,program,cores,steps,round,wall_s",
                        date + ",\"" + cpu + "\"," + j.program + "," + std::to_string(j.cores) + "," + steps + "," +
                            std::to_string(r + 1) + "," + std::to_string(wall));
    }
    for (int c : {1, 2}) {
      const double wall = stream.seconds(c, kStreamSweeps);
      times[{"stream-reference", c}].push_back(wall);
      std::printf("round %d  %-14s %d core(s)  %7.2f s\n", r + 1, "stream-reference", c, wall);
      bench::append_csv(src + "/bench/results/chute_run.csv", "date,cpu,program,cores,steps,round,wall_s",
                        date + ",\"" + cpu + "\",stream-reference," + std::to_string(c) + "," +
                            std::to_string(kStreamSweeps) + "," + std::to_string(r + 1) + "," + std::to_string(wall));
    }
  }
  auto med = [&](const std::string& p, int c) { return median(times[{p, c}]); };
  std::printf("\nmedians of %d interleaved runs of %s steps:\n", repeat, steps.c_str());
  for (const auto& [key, v] : times)
    std::printf("  %-14s %d core(s)  %7.2f s  (%.2f .. %.2f)\n", key.first.c_str(), key.second, median(v),
                *std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()));
  std::printf("silt: 2 threads / 1 thread %.2f\n", med("silt", 1) / med("silt", 2));
  std::printf("stream-reference (the kick's memory traffic): 2 threads / 1 thread %.2f\n",
              med("stream-reference", 1) / med("stream-reference", 2));
  if (!baseline.empty()) {
    std::printf("silt-baseline: 2 threads / 1 thread %.2f\n", med("silt-baseline", 1) / med("silt-baseline", 2));
    std::printf("silt / silt-baseline time: 1 thread %.3f, 2 threads %.3f\n", med("silt", 1) / med("silt-baseline", 1),
                med("silt", 2) / med("silt-baseline", 2));
  }
  if (lammps) {
    std::printf("lammps: 2 ranks / 1 process %.2f\n", med("lammps", 1) / med("lammps", 2));
    std::printf("lammps time / silt time: 1 core %.2f, 2 cores %.2f\n", med("lammps", 1) / med("silt", 1),
                med("lammps", 2) / med("silt", 2));
    if (!baseline.empty())
      std::printf("lammps time / silt-baseline time: 1 core %.2f, 2 cores %.2f\n",
                  med("lammps", 1) / med("silt-baseline", 1), med("lammps", 2) / med("silt-baseline", 2));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
