// SIGINT (Ctrl-C), SIGTERM (what batch schedulers send at a job's time limit) and SIGHUP (the
// terminal closed; left alone when ignored, as under nohup) as a request to stop: while a
// StopSignals lives, each signal sets a flag that runs poll at every step
// boundary, and optionally calls a function (which must be async-signal-safe), instead of killing
// the process; the run then writes all its outputs and the process exits with the signal's code
// (128 + signal: 130, 143, 129). The previous handlers come back when it is destroyed.
#pragma once

#include <atomic>

#include <csignal>

namespace silt::cli {

// Installs `sa` for SIGHUP unless SIGHUP is ignored (as under nohup, which must keep the process
// running when the terminal closes); the previous action goes to `old`. True when installed.
bool install_hangup(const struct sigaction& sa, struct sigaction* old = nullptr);

class StopSignals {
 public:
  explicit StopSignals(std::atomic<bool>* flag, void (*also)() = nullptr);
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The last signal caught (SIGINT, SIGTERM or SIGHUP), 0 when none.
  static int caught();
  // What the last signal did, for messages: "terminated (SIGTERM)", "hung up (SIGHUP)" or
  // "interrupted".
  static const char* describe();
  // 128 + the signal caught; 130 (SIGINT) when none was (a run stopped another way).
  static int exit_code();
};

}  // namespace silt::cli
