// What the shell sets up in GNU readline, shared by the REPL and its fuzz target: the commands that
// crash or hang readline 8.2's callback interface unbound, keys filtered, and completion by the
// session.
#pragma once

#include "shell/session.hpp"

namespace silt::cli {

// Keeps GNU readline 8.2 away from its crashes and hangs: removes the incremental history searches
// and the keyboard macros from every keymap, whatever keys the defaults or the user's inputrc gave
// them (call it after rl_initialize, which reads the inputrc; re-reading it with Ctrl-X Ctrl-R
// removes them again), Page Up/Down walking the history with the line's prefix instead; and reads
// keys through a filter that ends an unfinished vi-mode escape sequence before a byte readline
// would crash on, makes bytes that are no UTF-8 character '?', and holds counts at 1,000.
void guard_readline_keys();
// Completion of the word being typed by what the session's command expects (readline's own file
// name completion where it takes a file): install with install_completion(session).
void install_completion(const shell::Session* session);

}  // namespace silt::cli
