// `silt play SCRIPT`: the shell's commands from a file, each echoed with its line number.
// Stops at the first error with "SCRIPT:LINE: message" and exit code 2 (or goes on with
// --keep-going and exits 2 at the end).
#include <fstream>
#include <iostream>

#include "shell/commands.hpp"
#include "shell/session.hpp"

namespace silt::cli {

int play_command(const std::string& script, bool keep_going, int threads) {
  std::ifstream in(script);
  if (!in) return report_error("cannot read script '" + script + "'", 4);
  shell::Session session(std::cout, std::cerr, threads);
  std::string line;
  int n = 0;
  bool failed = false;
  while (std::getline(in, line)) {
    ++n;
    const auto start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    std::cout << script << ":" << n << "> " << line.substr(start) << "\n" << std::flush;
    if (!session.execute(line, script + ":" + std::to_string(n))) {
      failed = true;
      if (!keep_going) break;
    }
    if (session.quit_requested()) break;
  }
  session.execute("quit");
  return failed ? 2 : 0;
}

}  // namespace silt::cli
