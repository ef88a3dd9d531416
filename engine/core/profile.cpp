#include "silt/profile.hpp"

#include <chrono>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#define SILT_HAVE_TSC 1
#endif

namespace silt {
namespace {

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

#ifdef SILT_HAVE_TSC
// The counter's rate, measured between the first reading of the process and the first
// conversion, at least 20 ms apart.
struct Origin {
  uint64_t tsc = __rdtsc();
  double t = steady_seconds();
};
const Origin& origin() {
  static const Origin o;
  return o;
}
#endif

}  // namespace

uint64_t stage_ticks() {
#ifdef SILT_HAVE_TSC
  (void)origin();
  return __rdtsc();
#else
  return static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
}

double stage_tick_seconds() {
#ifdef SILT_HAVE_TSC
  static const double rate = [] {
    const Origin& o = origin();
    while (steady_seconds() - o.t < 0.02) {
    }
    const uint64_t tsc = __rdtsc();
    const double t = steady_seconds();
    return (t - o.t) / static_cast<double>(tsc - o.tsc);
  }();
  return rate;
#else
  return std::chrono::duration<double>(std::chrono::steady_clock::duration(1)).count();
#endif
}

}  // namespace silt
