// A shell session driven by fuzz input, for the targets without a terminal (session_fuzz.cpp) and
// with one (repl_fuzz.cpp): a fresh directory holding small scenes and scripts, a scene loaded
// first as the input's first byte says, each line made bounded (session_lines.hpp) before it is
// executed, a watchdog that interrupts a line (as Ctrl-C does) when it takes too long anyway, and
// the session's errors and messages read for reports of bugs.
#pragma once

#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include "session_lines.hpp"
#include "shell/session.hpp"

namespace silt::fuzz {

// Lines of one input, beyond the first load.
constexpr int kMaxSessionLines = 16;

// At initialisation, in the scratch directory: the files every session starts with, and the
// memory compile() sees. Starts the watchdog.
void prepare_sessions();

class SessionDriver {
 public:
  // In a fresh copy of the files, a session with pack_2d, bounce_dry or collision_normal loaded
  // (selector % 4 = 0, 1, 2), or with nothing, paste_iso or cavity_2d (selector % 4 = 3 and
  // (selector / 4) % 3 = 0, 1, 2).
  explicit SessionDriver(uint8_t selector);
  // Quits the session (joining a background run) and leaves the directory.
  ~SessionDriver();
  SessionDriver(const SessionDriver&) = delete;
  SessionDriver& operator=(const SessionDriver&) = delete;

  // Executes one line; false once the session has quit or had its lines.
  bool line(const std::string& text);
  shell::Session& session() { return *session_; }

 private:
  std::optional<Clock> clock();
  void check_output();

  std::ostringstream out_, err_;
  std::optional<shell::Session> session_;
  int lines_ = 0;
};

}  // namespace silt::fuzz
