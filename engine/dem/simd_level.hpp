// Which vector instructions the particle kernels use: AVX2 where the processor has it (chosen at
// run time, so that the build stays portable), or the baseline of the build (x86-64-v2: SSE4.2).
// Both run the same IEEE operations on each contact and give the same bits; tests compare them.
#pragma once

namespace silt::dem {

bool avx2_in_use();
// Limit the kernels to the baseline (true) or let them use AVX2 where present (false).
void limit_to_baseline(bool on);

}  // namespace silt::dem
