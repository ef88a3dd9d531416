// Which vector instructions the hot kernels (the DEM's pair scans and contact forces, the fluid's
// stencils) use: AVX2 where the processor has it (chosen at run time, so that the build stays
// portable), or the baseline of the build (x86-64-v2: SSE4.2). Both run the same IEEE operations
// on each value, without fused multiply-adds, and give the same bits; tests compare them.
#pragma once

// Before a loop whose iterations are independent (its arrays do not overlap): vectorise it
// without the run-time overlap checks GCC gives up on past a few arrays. (Clang, which builds
// the fuzz targets and the lint, keeps its own checks: its hint warns when it cannot vectorise.)
#if defined(__clang__)
#define SILT_IVDEP
#else
#define SILT_IVDEP _Pragma("GCC ivdep")
#endif

namespace silt {

bool avx2_in_use();
// Limit the kernels to the baseline (true) or let them use AVX2 where present (false).
void limit_to_baseline(bool on);

// Runs f() with its body (everything it calls inline) compiled for AVX2 when avx2_in_use(), else
// for the baseline: a loop written once, vectorised for both. f must not use fused multiply-adds
// (neither target enables them), so both give the same bits.
template <class F>
[[gnu::target("avx2"), gnu::flatten]] void run_avx2(const F& f) {
  f();
}
template <class F>
void run_simd(const F& f) {
  if (avx2_in_use()) run_avx2(f);
  else f();
}

}  // namespace silt
