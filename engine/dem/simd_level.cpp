#include "dem/simd_level.hpp"

#include <atomic>

namespace silt::dem {
namespace {

const bool kHasAvx2 = __builtin_cpu_supports("avx2");
std::atomic<bool> g_baseline{false};

}  // namespace

bool avx2_in_use() { return kHasAvx2 && !g_baseline.load(std::memory_order_relaxed); }

void limit_to_baseline(bool on) { g_baseline = on; }

}  // namespace silt::dem
