// libFuzzer target for the shell's command parser (scripts/fuzz.sh builds and runs it): any line
// either parses or throws ParseError with a column inside the line; nothing else may happen.
#include <cstddef>
#include <cstdint>
#include <string>

#include "shell/command_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string line(reinterpret_cast<const char*>(data), size);
  using namespace silt::shell;
  try {
    const auto c = parse_line(line);
    if (!c) return 0;
    if (c->name_col < 1 || static_cast<size_t>(c->name_col) > line.size()) __builtin_trap();
    for (const Token& t : c->args)
      if (t.col < 1 || static_cast<size_t>(t.col) > line.size()) __builtin_trap();
    try {
      check_command(*c);
    } catch (const ParseError&) {
    }
    try {
      const RunLength r = parse_run_length(c->args);
      if (r.kind == RunLength::kUntil) {
        std::vector<double> v(r.until.clauses.size(), 0.5);
        (void)r.until.holds(v);
      }
    } catch (const ParseError& e) {
      if (e.col < 0 || static_cast<size_t>(e.col) > line.size()) __builtin_trap();
    }
  } catch (const ParseError& e) {
    if (e.col < 0 || static_cast<size_t>(e.col) > line.size() + 1) __builtin_trap();
  }
  return 0;
}
