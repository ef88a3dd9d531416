// What keeps a fuzzed shell session short and inside its directory, and how its output shows a
// bug: lines are rewritten before the session sees them, errors are read after.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace silt::fuzz {

// Steps a run may take; longer ones are cut to this.
constexpr int64_t kFuzzRunSteps = 20;
// Frame sizes beyond this are cut to it (the scenes of the session have 160 x 120).
constexpr int kMaxFramePixels = 256;

struct Clock {
  int64_t step = 0;
  double dt = 0;
};
using ClockFn = std::function<std::optional<Clock>()>;  // nullopt when no scene is loaded

// The line with every path made a name in the current directory and every run length, and the
// values that set one (run.steps, run.time, prepare.max_steps) or the frame size, cut; the line
// itself when nothing needs changing (or it does not parse: the session refuses it as it is).
// A run until a condition also stops kFuzzRunSteps after the current step.
std::string bounded_line(const std::string& line, const ClockFn& now);

// Whether a line the session wrote on its error stream (or a background run's message) says that
// silt has a bug rather than that the input is wrong: a step's internal error, a failed
// assertion, an exception of the standard library.
bool reports_bug(const std::string& err_line);

}  // namespace silt::fuzz
