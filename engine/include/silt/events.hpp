// Numerical events raised by stages during a step, and the failure a run reports for them.
//
// A stage that meets something it cannot go on with (a NaN, an overlap beyond the limit, a
// solver that did not converge) raises an event with the index of the grain, pair or cell and a
// value; the lowest index wins, so the report does not depend on the number of threads. After
// the step, the diagnose() function of the module that owns the event turns it into a
// StepFailure that names the stage, the grain and the parameter to change (DESIGN.md, second
// tier of errors). Exceptions thrown inside a stage (a broken invariant, SILT_ASSERT) go to a
// separate slot: they are programming errors, not numerics.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>

namespace silt {

using EventId = uint8_t;
// The events of the built-in modules, in order of precedence (a step that raises several reports
// the first); a module may register more (register_module_event).
namespace event {
enum : EventId {
  kNonFiniteLate,  // dem: the last step's second half kick, run in this step, met a NaN or Inf (index: grain id)
  kNonFinite,      // dem: a grain's velocity or position is NaN or Inf (index: grain)
  kOverlap,        // dem: an overlap beyond limits.max_overlap (index: grain; value: overlap / radius)
  kBoxCollapse,    // shear: a controlled box length below twice the interaction range (index: axis)
  kRunaway,        // dem: kinetic energy beyond limits.energy_factor times the scene's (value: energy)
  kClockStalled,   // core: t + dt == t, the step lost in the rounding of the time (value: dt)
  kBuiltinCount
};
}
constexpr int kMaxEvents = 32;
// Returns the id of a module's own event (the same id for the same name).
EventId register_module_event(const std::string& name);
const std::string& event_name(EventId e);

// One event: how many times it was raised this step, and the lowest index with its value.
class EventSlot {
 public:
  static constexpr int64_t kNone = std::numeric_limits<int64_t>::max();
  EventSlot() = default;
  EventSlot(const EventSlot& o) { *this = o; }
  EventSlot& operator=(const EventSlot& o) {
    count_.store(o.count_.load());
    first_ = o.first_;
    value_ = o.value_;
    return *this;
  }
  void raise(int64_t index, double value) {
    count_.fetch_add(1, std::memory_order_relaxed);
    while (lock_.exchange(true, std::memory_order_acquire)) {
    }
    if (index < first_) {
      first_ = index;
      value_ = value;
    }
    lock_.store(false, std::memory_order_release);
  }
  bool raised() const { return count_.load(std::memory_order_relaxed) > 0; }
  int64_t count() const { return count_.load(std::memory_order_relaxed); }
  int64_t first() const { return first_; }
  double value() const { return value_; }
  void clear() {
    count_.store(0, std::memory_order_relaxed);
    first_ = kNone;
    value_ = 0;
  }

 private:
  std::atomic<int64_t> count_{0};
  std::atomic<bool> lock_{false};
  int64_t first_ = kNone;
  double value_ = 0;
};

struct Events {
  std::array<EventSlot, kMaxEvents> slot;
  EventSlot& operator[](EventId e) { return slot[e]; }
  const EventSlot& operator[](EventId e) const { return slot[e]; }
  bool any() const {
    for (const EventSlot& s : slot)
      if (s.raised()) return true;
    return false;
  }
  // Between steps (no stage runs): only the slots raised need it.
  void clear() {
    for (EventSlot& s : slot)
      if (s.raised()) s.clear();
  }
};

// An exception thrown by a stage (a broken invariant): the first one of the step is kept.
class InternalErrorSlot {
 public:
  InternalErrorSlot() = default;
  InternalErrorSlot(const InternalErrorSlot& o) { *this = o; }
  InternalErrorSlot& operator=(const InternalErrorSlot& o) {
    raised_.store(o.raised_.load());
    stage_ = o.stage_;
    message_ = o.message_;
    return *this;
  }
  void raise(const std::string& stage, const std::string& message) {
    if (raised_.exchange(true)) return;  // the first one is kept
    stage_ = stage;
    message_ = message;
  }
  bool raised() const { return raised_.load(); }
  const std::string& stage() const { return stage_; }
  const std::string& message() const { return message_; }
  void clear() {
    raised_ = false;
    stage_.clear();
    message_.clear();
  }

 private:
  std::atomic<bool> raised_{false};
  std::string stage_, message_;
};

// Why a run stopped on a numerical failure (exit code 3), or on an internal error.
struct StepFailure {
  bool failed = false;
  bool internal = false;  // a programming error, not the numerics
  EventId event = 0;
  int64_t step = 0;
  std::string stage;      // stage that detected it
  int64_t particle = -1;  // grain id, when one is to blame
  std::string parameter;  // the parameter to change
  std::string message;    // full sentence
};

}  // namespace silt
