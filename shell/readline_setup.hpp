// What the shell sets up in GNU readline, shared by the REPL and its fuzz target: the commands that
// crash or hang readline 8.2's callback interface unbound, keys filtered, and completion by the
// session.
#pragma once

#include <cstddef>

#include "shell/session.hpp"

namespace silt::cli {

// Keeps GNU readline 8.2 away from its crashes and hangs: removes the incremental history searches
// and the keyboard macros from every keymap, whatever keys the defaults or the user's inputrc gave
// them (call it after rl_initialize, which reads the inputrc; re-reading it with Ctrl-X Ctrl-R
// removes them again), Page Up/Down walking the history with the line's prefix instead; and reads
// keys through a filter that ends an unfinished vi-mode escape sequence before a byte readline
// would crash on, makes bytes that are no UTF-8 character '?', and holds counts at 1,000.
void guard_readline_keys();
// The length a line entered is held at: the whole line up to 4 KiB, else its first 4 KiB ended at a
// character's first byte, as the line is cut before each key. Readline inserts a run of typed-ahead
// characters as one key and runs the key that ends it (a paste's Enter) without reading it again,
// so no cut may come between them.
size_t held_line_end(const char* line);
// Completion of the word being typed by what the session's command expects (readline's own file
// name completion where it takes a file): install with install_completion(session).
void install_completion(const shell::Session* session);

}  // namespace silt::cli
