// What the shell sets up in GNU readline, shared by the REPL and its fuzz target: the key
// sequences that crash readline 8.2's callback interface unbound, and completion by the session.
#pragma once

#include "shell/session.hpp"

namespace silt::cli {

// Unbinds the incremental history searches (Ctrl-R, Ctrl-S) and keyboard macros (Ctrl-X ( ) e);
// Page Up/Down walk the history with the line's prefix instead. Reads keys through a filter that
// ends an unfinished escape sequence of vi mode where readline would crash on the next byte.
void unbind_crashing_keys();
// Completion of the word being typed by what the session's command expects (readline's own file
// name completion where it takes a file): install with install_completion(session).
void install_completion(const shell::Session* session);

}  // namespace silt::cli
