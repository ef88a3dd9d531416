// Text helpers for messages: short number formatting and "did you mean" distances (the engine's and
// the shell's).
#pragma once

#include <string>
#include <string_view>

namespace silt {

// A number with `digits` significant digits ("0.0001", "2.5e+05").
std::string format_number(double x, int digits = 6);

// Levenshtein distance (insertions, deletions, substitutions).
size_t edit_distance(std::string_view a, std::string_view b);

}  // namespace silt
