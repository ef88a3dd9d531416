// `silt shell`: the interactive REPL on GNU readline (line editing, history in ~/.silt_history,
// tab completion of commands, keys, observables and file names).
//
// readline's callback interface keeps the prompt alive while a background run prints: the loop
// waits on stdin and on a self-pipe written by the SIGINT handler, with a timeout to print the
// background run's messages. Ctrl-C during a foreground run pauses it at the next step boundary
// (and abandons a sourced script); at the prompt it clears the line. SIGTERM (a scheduler, a
// closing terminal's session manager) pauses the run and ends the session as `quit` does, exit 143;
// SIGHUP (the terminal closed) does the same, exit 129, unless it is ignored (nohup).
//
// Without a terminal on standard input (a pipe, a file, a scheduler's job), or on one that cannot
// move the cursor up (TERM=dumb), there is no line editing at all: lines are read as they are, a
// control character is part of the line, and nothing of readline runs after its set-up (its
// callback interface crashes on some key sequences, below); the latter still has a prompt and the
// history file.
//
// On a terminal, the commands that crash GNU readline 8.2's callback interface (history
// searches, keyboard macros and others) are unbound by function: the list, with what each did, is
// `crashes_readline` in shell/readline_setup.cpp. The arrow keys still walk the history, and a
// prefix of the line walks it with Page Up/Down.
//
// Two libraries in the process export the rl_* symbols: GNU readline, which silt links, and
// libedit, which Mesa's llvmpipe (OSMesa -> libLLVM) brings in. The dynamic linker binds each
// symbol to the first library in breadth-first load order; readline is a direct dependency of the
// executable (CMakeLists.txt links it ahead of the renderer) and libedit an indirect one, so
// readline wins. The start-up check below (rl_library_version) says so if that ever changes, and
// tests/shell/repl_test.cpp drives completion and history through a pseudo-terminal.
#include <fcntl.h>
#include <readline/history.h>
#include <readline/readline.h>
#include <sys/select.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <utility>

#include "shell/commands.hpp"
#include "shell/readline_setup.hpp"
#include "shell/session.hpp"
#include "shell/stop_signals.hpp"
#include "silt/errors.hpp"

namespace silt::cli {
namespace {

constexpr int kHistoryLines = 5000;

std::string history_path() {
  const char* home = std::getenv("HOME");
  return std::string(home ? home : ".") + "/.silt_history";
}

// True when the rl_* symbols are GNU readline's: libedit's emulation calls itself
// "EditLine wrapper" and claims readline 4.2.
bool gnu_readline() {
  return rl_library_version && std::strncmp(rl_library_version, "EditLine", 8) != 0 && rl_readline_version >= 0x0600;
}

// Each line goes to the history file as it is entered, so a session that is killed or hung up
// loses nothing, and concurrent sessions add to the file instead of overwriting each other.
void remember(const char* line) {
  add_history(line);
  const std::string path = history_path();
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);  // append_history needs the file
  if (fd < 0) return;
  ::close(fd);
  if (append_history(1, path.c_str()) == 0) history_truncate_file(path.c_str(), kHistoryLines);
}

shell::Session* g_session = nullptr;
int g_pipe[2] = {-1, -1};
std::string g_pending;
bool g_have_line = false, g_eof = false;

volatile std::sig_atomic_t g_terminated = 0;

// SIGINT pauses a run (or clears the line); SIGTERM and SIGHUP also end the session, as `quit`
// does, with the signal's exit code.
extern "C" void on_shell_signal(int sig) {
  if (sig == SIGTERM || sig == SIGHUP) g_terminated = sig;
  if (g_session) g_session->interrupt();
  const char c = 'i';
  if (g_pipe[1] >= 0) (void)!::write(g_pipe[1], &c, 1);
}

extern "C" void on_line(char* line) {
  // Removed here, inside the handler, so that readline does not draw the prompt again before the
  // command's output (which would then overwrite it from column 0); installed again afterwards.
  rl_callback_handler_remove();
  if (!line) {
    g_eof = true;
  } else {
    line[silt::cli::held_line_end(line)] = '\0';  // (a paste's Enter read with its last characters)
    g_pending = line;
    g_have_line = true;
    if (*line) remember(line);
    std::free(line);
  }
}

// A line longer than this is refused whole (the input of `silt shell < /dev/zero` has no end of
// line: it was kept, and searched again from its start after every read of 4 KiB).
constexpr size_t kMaxPlainLine = size_t{1} << 20;

// The shell without a terminal: plain lines (a pipe, a file), a background run's messages
// printed between them, Ctrl-C (SIGINT) pausing a run as on a terminal. On a terminal without line
// editing (`prompted`), a prompt is printed whenever a line is awaited (again after a background
// run's messages, on a line of its own) and each line entered goes to the history file. From a
// pipe or a file the lines are a script that goes on after an error: the exit code is the highest
// of its errors' (as `silt play --keep-going`'s), a background run that failed numerically 3, an
// output lost 4; on a terminal the user has seen them, and it is 0. `code`: the scene's load's.
int plain_lines(shell::Session& session, bool prompted, int code) {
  auto execute = [&](const std::string& line) {
    if (!session.execute(line) && !prompted) code = std::max(code, session.last_error_code());
  };
  std::string buf;
  size_t scanned = 0;     // buf[0, scanned) holds no end of line
  bool too_long = false;  // the line being read is past kMaxPlainLine: dropped up to its end
  bool eof = false;
  bool prompt_due = prompted, prompt_shown = false;
  while (!session.quit_requested() && !g_terminated) {
    const auto messages = session.take_messages();
    if (!messages.empty() && std::exchange(prompt_shown, false)) std::cout << "\n";
    for (const auto& m : messages) std::cout << m << "\n";
    if (!messages.empty()) {
      std::cout << std::flush;
      prompt_due = prompted;
    }
    const auto nl = buf.find('\n', scanned);
    if (nl == std::string::npos) scanned = buf.size();
    if (nl == std::string::npos && buf.size() > kMaxPlainLine) {
      if (!too_long) {
        std::cerr << "error: a line longer than " << kMaxPlainLine << " bytes: ignored\n";
        if (!prompted) code = std::max(code, static_cast<int>(ExitCode::kScene));
      }
      too_long = true;
      buf.clear();
      scanned = 0;
    }
    if (nl != std::string::npos) {
      std::string line = buf.substr(0, nl);
      buf.erase(0, nl + 1);
      scanned = 0;
      if (std::exchange(too_long, false)) continue;  // the end of a line refused above
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (prompted && !line.empty()) remember(line.c_str());
      execute(line);
      prompt_due = prompted;
      prompt_shown = false;
      char drain[64];  // a Ctrl-C that paused the command is spent
      while (::read(g_pipe[0], drain, sizeof drain) > 0) {
      }
      continue;
    }
    if (eof) {
      if (!buf.empty() && !too_long) execute(std::exchange(buf, std::string()));
      break;
    }
    if (std::exchange(prompt_due, false)) {
      std::cout << session.prompt() << std::flush;
      prompt_shown = true;
    }
    fd_set fds;
    FD_ZERO(&fds);
    FD_SET(STDIN_FILENO, &fds);
    FD_SET(g_pipe[0], &fds);
    timeval tv{0, 200000};
    const int r = select(std::max(STDIN_FILENO, g_pipe[0]) + 1, &fds, nullptr, nullptr, &tv);
    if (r > 0 && FD_ISSET(g_pipe[0], &fds)) {
      char drain[64];
      (void)!::read(g_pipe[0], drain, sizeof drain);
      if (std::exchange(prompt_shown, false)) {  // Ctrl-C at the prompt: the terminal dropped the line
        std::cout << "\n";
        prompt_due = true;
      }
    }
    if (r > 0 && FD_ISSET(STDIN_FILENO, &fds)) {
      char chunk[4096];
      const ssize_t n = ::read(STDIN_FILENO, chunk, sizeof chunk);
      if (n > 0) buf.append(chunk, static_cast<size_t>(n));
      else if (n == 0 || errno != EINTR) eof = true;
    }
  }
  if (prompt_shown) std::cout << "\n";  // end of input typed at the prompt
  session.execute("quit");
  // (the texts were printed with the run's messages)
  if (!prompted) code = std::max(code, session.take_unreported().code);
  return g_terminated ? 128 + g_terminated : code;
}

}  // namespace

int shell_command(const std::string& scene, int threads) {
  shell::Session session(std::cout, std::cerr, threads);
  session.set_progress(::isatty(STDERR_FILENO));
  g_session = &session;
  if (::pipe(g_pipe) != 0) return report_error("cannot create a pipe", 4);
  ::fcntl(g_pipe[0], F_SETFL, O_NONBLOCK);
  struct sigaction sa {};
  sa.sa_handler = on_shell_signal;
  // A write to a full pipe (stdout read by a slower program) blocked when the signal comes is
  // resumed, not failed with EINTR, which would put std::cout in error and lose the rest.
  sa.sa_flags = SA_RESTART;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  install_hangup(sa);
  const bool terminal = ::isatty(STDIN_FILENO);
  if (terminal) {
    rl_catch_signals = 0;
    install_completion(&session);
    rl_readline_name = "silt";
    rl_initialize();  // reads the terminal's description (TERM) and the inputrc
  }
  // A terminal that cannot move the cursor up (TERM dumb, unset or not described, as in an
  // editor's shell buffer) gets plain lines too: readline 8.2 would scroll the line sideways
  // there, and that display reads past its buffer after a count's insertion of about 1,000
  // characters (AddressSanitizer: heap-buffer-overflow in rl_redisplay from _rl_arg_dispatch).
  const char* up = terminal ? rl_get_termcap("up") : nullptr;
  if (!up || !*up) {
    const bool loaded = scene.empty() || session.execute("load " + shell::quoted_word(scene));
    if (terminal) using_history();
    const int code = plain_lines(session, terminal, loaded || terminal ? 0 : session.last_error_code());
    g_session = nullptr;
    ::close(g_pipe[0]);
    ::close(g_pipe[1]);
    return code;
  }
  guard_readline_keys();
  using_history();
  read_history(history_path().c_str());
  stifle_history(kHistoryLines);
  std::cout << "silt " << SILT_VERSION << " shell (" << (gnu_readline() ? "GNU readline " : "line editor ")
            << rl_library_version << "): help lists the commands, quit leaves.\n";
  if (!gnu_readline())
    std::cout << "warning: the rl_* functions resolve to another library than GNU readline; history and completion may "
                 "not work\n";
  if (!scene.empty()) session.execute("load " + shell::quoted_word(scene));
  std::string prompt = session.prompt();
  rl_callback_handler_install(prompt.c_str(), on_line);
  while (!session.quit_requested()) {
    fd_set fds;
    FD_ZERO(&fds);
    FD_SET(STDIN_FILENO, &fds);
    FD_SET(g_pipe[0], &fds);
    timeval tv{0, 200000};
    const int r = select(std::max(STDIN_FILENO, g_pipe[0]) + 1, &fds, nullptr, nullptr, &tv);
    if (r > 0 && FD_ISSET(g_pipe[0], &fds)) {
      char buf[64];
      (void)!::read(g_pipe[0], buf, sizeof buf);
      // Ctrl-C at the prompt: drop the line being typed.
      rl_replace_line("", 0);
      std::cout << "^C\n";
      rl_on_new_line();
      rl_redisplay();
    }
    // Messages of a background run, printed above the prompt.
    const auto messages = session.take_messages();
    if (!messages.empty()) {
      rl_clear_visible_line();
      for (const auto& m : messages) std::cout << m << "\n";
      std::cout << std::flush;
      rl_forced_update_display();
    }
    if (g_terminated) break;
    if (r > 0 && FD_ISSET(STDIN_FILENO, &fds)) rl_callback_read_char();
    if (g_eof) break;
    if (g_have_line) {
      g_have_line = false;
      session.execute(g_pending);
      // A Ctrl-C that paused the command is spent: do not clear the next prompt with it.
      char buf[64];
      while (::read(g_pipe[0], buf, sizeof buf) > 0) {
      }
      if (session.quit_requested()) break;
      prompt = session.prompt();
      rl_callback_handler_install(prompt.c_str(), on_line);
    } else if (r == 0) {
      // Refresh the prompt (time of a background run).
      const std::string p = session.prompt();
      if (p != prompt) {
        prompt = p;
        rl_set_prompt(prompt.c_str());
        rl_redisplay();
      }
    }
  }
  rl_callback_handler_remove();
  if (g_eof || g_terminated) std::cout << "\n";
  session.execute("quit");
  g_session = nullptr;
  ::close(g_pipe[0]);
  ::close(g_pipe[1]);
  return g_terminated ? 128 + g_terminated : 0;
}

}  // namespace silt::cli
