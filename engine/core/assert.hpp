// Invariants of the engine (DESIGN.md, third tier of errors: programming errors).
//
// SILT_ASSERT(cond, message) checks a precondition or a postcondition that no input can break:
// if it fails, silt has a bug. It throws silt::InternalError with the file, the line, the
// condition and the message; inside a stage the executor turns it into the step's internal error,
// so a broken invariant stops the run with a report instead of corrupting it, and the shell
// survives. The checks are cheap (outside the per-grain and per-pair loops) and always on;
// SILT_DEBUG_ASSERT is for checks inside those loops, compiled only without NDEBUG.
#pragma once

#include <stdexcept>
#include <string>

namespace silt {

class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] inline void assertion_failed(const char* file, int line, const char* cond, const std::string& message) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) + ": assertion '" + cond + "' failed: " + message);
}

}  // namespace silt

#define SILT_ASSERT(cond, message)                                             \
  do {                                                                         \
    if (!(cond)) ::silt::assertion_failed(__FILE__, __LINE__, #cond, message); \
  } while (false)

#ifdef NDEBUG
#define SILT_DEBUG_ASSERT(cond, message) \
  do {                                   \
  } while (false)
#else
#define SILT_DEBUG_ASSERT(cond, message) SILT_ASSERT(cond, message)
#endif
