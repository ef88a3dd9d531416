// Wall time per stage, kept in the State so that the shell and the summary show it.
//
// Stages are timed with the processor's time-stamp counter where there is one (x86: a few
// nanoseconds per reading, against about 16 for the system's steady clock; a step of a small
// system has a dozen stages), converted to seconds with a rate measured against the steady
// clock.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <string>

namespace silt {

// A reading of the stage clock, in ticks.
uint64_t stage_ticks();
// Seconds per tick of the stage clock.
double stage_tick_seconds();

struct StageTime {
  uint64_t ticks = 0;
  int64_t calls = 0;
  double seconds() const { return static_cast<double>(ticks) * stage_tick_seconds(); }
};

// Stage name -> time. A copy is another profile (its id differs): the executors keep pointers to
// the entries of the profile they last timed into, and look them up again for another one.
class Profile {
 public:
  using Map = std::map<std::string, StageTime>;
  Profile() : id_(next_id()) {}
  Profile(const Profile& o) : stages_(o.stages_), id_(next_id()) {}
  Profile& operator=(const Profile& o) {
    stages_ = o.stages_;
    id_ = next_id();
    return *this;
  }
  StageTime& operator[](const std::string& name) { return stages_[name]; }
  Map::const_iterator begin() const { return stages_.begin(); }
  Map::const_iterator end() const { return stages_.end(); }
  bool empty() const { return stages_.empty(); }
  const Map& stages() const { return stages_; }
  uint64_t id() const { return id_; }

 private:
  static uint64_t next_id() {
    static std::atomic<uint64_t> n{0};
    return ++n;
  }
  Map stages_;
  uint64_t id_;
};

}  // namespace silt
