// Which vector instructions the hot kernels use: AVX-512 (512-bit vectors; the fluid's stencils and
// transforms) or AVX2 (the DEM's pair scans and contact forces, and the fluid where there is no
// AVX-512) where the processor has them, chosen at run time so that the build stays portable, or
// the baseline of the build (x86-64-v2: SSE4.2). All run the same IEEE operations on each value,
// without fused multiply-adds, and give the same bits; tests compare them.
#pragma once

#include <algorithm>
#include <string>

// Before a loop whose iterations are independent (its arrays do not overlap): vectorise it
// without the run-time overlap checks GCC gives up on past a few arrays. (Clang, which builds
// the fuzz targets and the lint, keeps its own checks: its hint warns when it cannot vectorise.)
#if defined(__clang__)
#define SILT_IVDEP
#else
#define SILT_IVDEP _Pragma("GCC ivdep")
#endif

namespace silt {

// Ordered: each level has the instructions of the one before.
enum class SimdLevel { kBaseline, kAvx2, kAvx512 };

// The level the kernels use: the processor's widest, at most the limit.
SimdLevel simd_level();
SimdLevel simd_widest();  // the processor's widest
inline bool avx2_in_use() { return simd_level() >= SimdLevel::kAvx2; }
// Limit the kernels to `most` (kAvx512: no limit); tests compare the levels' bits.
void limit_simd(SimdLevel most);
// "baseline", "avx2", "avx512", and back (false for another name).
const char* simd_name(SimdLevel level);
bool simd_level_named(const std::string& name, SimdLevel& level);

// Runs f() with its body (everything it calls inline) compiled for the widest level in use, at
// most kMost (a kernel whose loops gain nothing from 512-bit vectors stays at AVX2). AVX-512 has
// fused multiply-add instructions (AVX2's target here does not enable FMA): what keeps them out is
// -ffp-contract=off, formulas that GCC 12 cannot turn into them anyway (a product added in one lane
// and subtracted in the next became vfmsubadd: add the product of a negated factor instead), and
// scripts/lint.sh, which refuses a build that holds one. So every level gives the same bits.
template <class F>
[[gnu::target("avx2"), gnu::flatten]] void run_avx2(const F& f) {
  f();
}
// (GCC keeps to 256-bit vectors unless told; clang, which builds the fuzz targets, takes no such
// option in the attribute.)
#if defined(__clang__)
#define SILT_AVX512_TARGET "avx2,avx512f,avx512vl,avx512dq,avx512bw"
#else
#define SILT_AVX512_TARGET "avx2,avx512f,avx512vl,avx512dq,avx512bw,prefer-vector-width=512"
#endif
template <class F>
[[gnu::target(SILT_AVX512_TARGET), gnu::flatten]] void run_avx512(const F& f) {
  f();
}
template <SimdLevel kMost = SimdLevel::kAvx512, class F>
void run_simd(const F& f) {
  const SimdLevel level = std::min(simd_level(), kMost);
  if (level == SimdLevel::kAvx512) run_avx512(f);
  else if (level == SimdLevel::kAvx2) run_avx2(f);
  else f();
}

}  // namespace silt
