// `silt play SCRIPT`: the shell's commands from a file, each echoed with its line number.
// Stops at the first error with "SCRIPT:LINE:COL: message" and exit code 2, 3 when a run failed
// numerically, 4 when a file could not be read or written (INTERFACE.md); --keep-going goes on
// and exits with the highest code at the end.
// SIGINT, SIGTERM or SIGHUP pauses the run going on at a step boundary, as in `silt run`; the
// script then stops, its outputs are written (`quit`), and the exit code is the signal's (130,
// 143, 129).
// Relative input files are looked for in the current directory, then beside the script.
#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "shell/command_parser.hpp"
#include "shell/commands.hpp"
#include "shell/session.hpp"
#include "shell/stop_signals.hpp"
#include "silt/input_files.hpp"

namespace silt::cli {
namespace {

// What a background run printed (watch lines, its end) goes out after each command, in order
// with the commands' own output; a run that failed on its own is an error of the script (3), and
// so is an output it could no longer write (4). Returns the exit code it asks for, 0 for none.
int flush_background(shell::Session& session, const std::string& where) {
  for (const std::string& m : session.take_messages()) std::cout << m << "\n";
  std::cout << std::flush;
  const shell::Session::Unreported u = session.take_unreported();
  for (const std::string& line : u.lines) std::cerr << where << ":1: " << line << "\n" << std::flush;
  return u.code;
}

shell::Session* g_played = nullptr;
std::atomic<bool> g_stop{false};
void interrupt_session() {
  if (g_played) g_played->interrupt();
}

}  // namespace

int play_command(const std::string& script, bool keep_going, int threads) {
  try {
    check_input_file(script, "script", kMaxTextFileBytes);
  } catch (const IoError& e) {
    return report_error(e.what(), 4);
  }
  std::ifstream in(script);
  if (!in) return report_error("cannot read script '" + script + "'", 4);
  shell::Session session(std::cout, std::cerr, threads);
  session.set_script(script);
  session.set_echo_sources(true);
  session.set_keep_going(keep_going);
  g_played = &session;
  g_stop = false;
  StopSignals stop(&g_stop, interrupt_session);
  std::string line;
  int n = 0;
  int code = 0;
  auto failed = [&](int c) { code = std::max(code, c); };
  while (std::getline(in, line)) {
    ++n;
    line = shell::script_line(line, n);
    const auto start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    std::cout << script << ":" << n << "> " << shell::printable_line(line.substr(start)) << "\n" << std::flush;
    const std::string where = script + ":" + std::to_string(n);
    if (!session.execute(line, where)) failed(session.last_error_code());
    if (const int c = flush_background(session, where); c != 0) failed(c);
    if (g_stop) {
      std::cerr << where << ": " << StopSignals::describe() << ": the script stops here\n";
      break;
    }
    if ((code != 0 && !keep_going) || session.quit_requested()) break;
  }
  session.execute("quit");
  if (const int c = flush_background(session, script + ":" + std::to_string(n)); c != 0) failed(c);
  g_played = nullptr;
  return g_stop ? StopSignals::exit_code() : code;
}

}  // namespace silt::cli
