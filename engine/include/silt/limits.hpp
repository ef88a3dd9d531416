// The longest run silt takes, in steps, for every reader of a run length: run.steps and run.time
// in a scene, --steps and --time, the shell's `run`, `every` and its checkpoints' counts. A
// header of its own, so that the shell's command parser reads it without the engine's model.
#pragma once

#include <cmath>
#include <cstdint>

namespace silt {

// An int64_t holds it with room to spare (a step's count plus one never overflows).
inline constexpr int64_t kMaxRunSteps = 9'000'000'000'000'000'000;
// How messages write it.
inline constexpr const char* kMaxRunStepsText = "9e18";
// Runs of more fixed steps than this are said before they start (`silt run`, the shell's `run`).
inline constexpr int64_t kLongRunSteps = 100'000'000;

// The relative distance within which a time t, a sum of steps, is taken to be at a value: its
// rounding (t is 9.9999999999999829e-05 after 100 steps of 1e-6 s; a billion steps' rounding).
inline constexpr double kTimeSlack = 1e-9;
// How far from `value` a time is still at it.
inline double time_slack(double value) { return kTimeSlack * std::abs(value); }
// Whether t is at `value` (`run until t <= T` holds at t = T shown).
inline bool at_time(double t, double value) { return std::abs(t - value) <= time_slack(value); }
// Whether t is at or past `since` (--average-from, `stats since`).
inline bool at_or_after(double t, double since) { return t >= since - time_slack(since); }

}  // namespace silt
