#pragma once
// Whether the hand-vectorised kernels (add_scaled.hpp, supernode_kernels_avx2.hpp) take their
// AVX2 paths: the CPU has AVX2 (checked at run time; the build targets baseline x86-64) and
// no caller turned them off. Both paths give the same bits (no fused multiply-add), so this
// only changes speed; tests turn it off to compare.
namespace sinew {

bool use_avx2();
void allow_avx2(bool allowed);

}  // namespace sinew
