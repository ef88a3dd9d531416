// libFuzzer target for whole shell sessions on a terminal, as `silt shell` reads one
// (shell/repl.cpp): the first byte picks the scene loaded first, the rest are key presses fed to
// GNU readline's callback interface through rl_instream (a pipe), with the same key sequences
// unbound, the same line handler and the same completion; each line it returns is made bounded
// and executed by a Session (session_driver.hpp), at most kMaxSessionLines of them. Seeds: those
// of session_fuzz, and key sequences (seeds.sh: completion, history, editing, vi mode).
#include <readline/history.h>
#include <readline/readline.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "session_driver.hpp"
#include "shell/readline_setup.hpp"

namespace {

silt::fuzz::SessionDriver* g_driver = nullptr;
std::string g_pending;
bool g_have_line = false, g_eof = false;

extern "C" void on_line(char* line) {
  rl_callback_handler_remove();  // as repl.cpp: installed again after the command
  if (!line) {
    g_eof = true;
    return;
  }
  g_pending = line;
  g_have_line = true;
  if (*line) add_history(line);  // not to a file: the history of this input only
  std::free(line);
}

// What one input may have left in readline: a half-typed key sequence or line, vi mode, history.
void reset_readline() {
  rl_callback_sigcleanup();
  rl_free_line_state();
  rl_replace_line("", 1);
  rl_callback_handler_remove();
  rl_set_keymap(emacs_standard_keymap);
  rl_editing_mode = 1;
  rl_clear_history();  // with the undo lists of edited history lines
}

// readline's line after a key, while it is being edited (not once handed over, when readline's
// fields are left as they were): rl_end bytes with no NUL among them, the point within it.
// readline 8.2's forward character search loops forever on a NUL before the line's end.
void check_line() {
  if (!rl_line_buffer || !RL_ISSTATE(RL_STATE_CALLBACK) || RL_ISSTATE(RL_STATE_DONE)) return;
  const auto end = static_cast<size_t>(std::max(rl_end, 0));
  if (std::strlen(rl_line_buffer) != end || rl_point < 0 || rl_point > rl_end)
    silt::fuzz::bug("readline's line broken: " + std::to_string(std::strlen(rl_line_buffer)) +
                    " bytes before a NUL, end " + std::to_string(rl_end) + ", point " + std::to_string(rl_point));
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  silt::fuzz::enter_scratch_dir(argc, argv);
  silt::fuzz::prepare_sessions();
  // A terminal as interactive users have one, and no one's ~/.inputrc.
  setenv("TERM", "xterm", 1);
  setenv("COLUMNS", "80", 1);
  setenv("LINES", "24", 1);
  setenv("INPUTRC", "/dev/null", 1);
  rl_catch_signals = 0;
  rl_catch_sigwinch = 0;
  rl_readline_name = "silt";
  rl_outstream = std::fopen("/dev/null", "w");
  rl_initialize();
  silt::cli::guard_readline_keys();
  rl_variable_bind("bell-style", "none");
  using_history();
  if (!rl_library_version || std::strncmp(rl_library_version, "EditLine", 8) == 0)
    silt::fuzz::bug("the rl_* functions are not GNU readline's: link readline first");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0 || size > 60000) return 0;  // the keys must fit in the pipe
  silt::fuzz::SessionDriver driver(data[0]);
  g_driver = &driver;
  silt::cli::install_completion(&driver.session());
  int fds[2];
  if (::pipe(fds) != 0) silt::fuzz::bug("cannot create a pipe");
  if (::write(fds[1], data + 1, size - 1) != static_cast<ssize_t>(size - 1)) silt::fuzz::bug("cannot fill the pipe");
  ::close(fds[1]);
  rl_instream = ::fdopen(fds[0], "r");
  g_have_line = g_eof = false;
  std::string prompt = driver.session().prompt();
  rl_callback_handler_install(prompt.c_str(), on_line);
  // One key per call, as the REPL calls it when its input is readable; the end of the pipe is
  // the end of input (Ctrl-D). A key sequence may take several bytes: the calls are bounded.
  for (size_t calls = 0; !g_eof && calls < size + 16; ++calls) {
    rl_callback_read_char();
    check_line();
    if (!g_have_line) continue;
    g_have_line = false;
    if (!driver.line(g_pending)) break;
    prompt = driver.session().prompt();
    rl_callback_handler_install(prompt.c_str(), on_line);
  }
  reset_readline();
  std::fclose(rl_instream);
  rl_instream = nullptr;
  g_driver = nullptr;
  return 0;
}
