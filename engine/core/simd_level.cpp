#include "core/simd_level.hpp"

#include <atomic>

namespace silt {
namespace {

// Also at static initialisation, which may come before the run-time library has read the
// processor's features: read them first. (The library counts AVX-512 only where the operating
// system saves its registers.)
SimdLevel detect() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512bw"))
    return SimdLevel::kAvx512;
  return __builtin_cpu_supports("avx2") ? SimdLevel::kAvx2 : SimdLevel::kBaseline;
}
const SimdLevel kWidest = detect();
std::atomic<SimdLevel> g_most{SimdLevel::kAvx512};

}  // namespace

SimdLevel simd_level() { return std::min(kWidest, g_most.load(std::memory_order_relaxed)); }

SimdLevel simd_widest() { return kWidest; }

void limit_simd(SimdLevel most) { g_most = most; }

const char* simd_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::kAvx512: return "avx512";
    case SimdLevel::kAvx2: return "avx2";
    default: return "baseline";
  }
}

bool simd_level_named(const std::string& name, SimdLevel& level) {
  for (SimdLevel l : {SimdLevel::kBaseline, SimdLevel::kAvx2, SimdLevel::kAvx512})
    if (name == simd_name(l)) {
      level = l;
      return true;
    }
  return false;
}

}  // namespace silt
