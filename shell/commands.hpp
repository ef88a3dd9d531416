// Subcommands of the `silt` executable (INTERFACE.md).
#pragma once

#include <string>
#include <vector>

namespace silt::cli {

struct RunArgs {
  std::string scene;
  std::vector<std::string> sets;
  int64_t steps = -1;
  double time = -1;
  int threads = 0;
  std::string stats, summary, observe, restore, save, frames, vtk;
  int64_t frame_every = 0, vtk_every = 0;
  int64_t every = 0;
  double average_from = 0;
  bool quiet = false;
};

int run_command(const RunArgs& a);

struct CheckArgs {
  std::string scene;
  std::vector<std::string> sets;
  int threads = 0;
};
int check_command(const CheckArgs& a);

// The interactive shell, and scripts of its commands.
int shell_command(const std::string& scene, int threads);
int play_command(const std::string& script, bool keep_going, int threads);

// Print "silt: <message>" on stderr and return the exit code.
int report_error(const std::string& message, int code);

}  // namespace silt::cli
