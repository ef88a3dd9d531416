// Errors that cross the engine's public boundary.
//
// Three tiers (DESIGN.md): input errors carry the file location of the offending value and are
// thrown as SceneError; numerical events during a step are raised in State::events and turned
// into a StepFailure by the modules' diagnoses (silt/events.hpp); programming errors are
// SILT_ASSERT (engine/core/assert.hpp), which a step reports as its internal error.
#pragma once

#include <stdexcept>
#include <string>

namespace silt {

// Where a value came from: a scene file, a `--set` override, or a string given to the parser.
struct FileLoc {
  std::string file;
  int line = 0;             // 1-based; 0 when unknown
  int col = 0;              // 1-based; 0 when unknown
  std::string str() const;  // "file:line:col"
};

// Process exit codes of the command-line contract (INTERFACE.md).
enum class ExitCode : int { kOk = 0, kUsage = 1, kScene = 2, kNumerical = 3, kIo = 4 };

// A scene that cannot be read or cannot be simulated. what() is "file:line:col: message".
class SceneError : public std::runtime_error {
 public:
  SceneError(FileLoc loc, const std::string& message);
  const FileLoc& loc() const { return loc_; }
  const std::string& message() const { return message_; }

 private:
  FileLoc loc_;
  std::string message_;
};

// A file that could not be written or read (exit code 4).
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace silt
