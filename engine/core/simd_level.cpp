#include "core/simd_level.hpp"

#include <atomic>

namespace silt {
namespace {

// Also at static initialisation, which may come before the run-time library has read the
// processor's features: read them first.
bool detect_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}
const bool kHasAvx2 = detect_avx2();
std::atomic<bool> g_baseline{false};

}  // namespace

bool avx2_in_use() { return kHasAvx2 && !g_baseline.load(std::memory_order_relaxed); }

void limit_to_baseline(bool on) { g_baseline = on; }

}  // namespace silt
