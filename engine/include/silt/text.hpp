// Text helpers for messages: short number formatting and "did you mean" distances (the engine's and
// the shell's).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace silt {

// A number with `digits` significant digits ("0.0001", "2.5e+05").
std::string format_number(double x, int digits = 6);
// A positive bound to `digits` significant digits, rounded down: a value below the one printed
// is below the bound ("reduce fluid.dt below 0.01235" for 0.012346 rounded up past it).
std::string format_bound_below(double x, int digits);
// x, past `limit`, to `digits` significant digits or as many more as it takes to differ from it
// ("0.6 exceeds 0.6", "1.6 above 1.6").
std::string format_past(double x, double limit, int digits);

// Levenshtein distance (insertions, deletions, substitutions), or `limit` when it is at least
// that: a search for the closest name stops early on names that cannot beat the best so far.
size_t edit_distance(std::string_view a, std::string_view b, size_t limit = SIZE_MAX);

// The offset of the first byte of `text` that is not part of a well-formed UTF-8 character
// (overlong forms, surrogates and code points beyond U+10FFFF included), or npos.
size_t first_invalid_utf8(std::string_view text);

// A control character: below U+0020, or DEL (what a terminal acts on instead of showing).
constexpr bool is_control(char ch) {
  const auto c = static_cast<unsigned char>(ch);
  return c < 0x20 || c == 0x7F;
}

// `text` as a TOML basic string: in double quotes, with quotes, backslashes and control
// characters escaped (\", \\, \n, \t, \u0007), so that a name read from a scene prints as one
// line and reads back as itself.
std::string toml_quoted(std::string_view text);

}  // namespace silt
