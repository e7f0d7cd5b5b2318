#pragma once
// The block solve's passes over one supernode (supernodal_block_solve.cpp: forward, L y = b
// on the block's rows, and backward, L^T z = y) for blocks 4, 8 or 16 wide, in AVX2: 4
// lanes where Eigen's baseline build uses 2. Each entry sees the same multiplies, adds and
// subtractions in the same order as there (no fused multiply-add), so the bits are the same;
// callers check use_avx2() (engine/core/cpu_features.hpp) first.
#include "engine/solve/supernode_view.hpp"

namespace sinew {

template <int W>
void forward_avx2(const SupernodeView& s, double* y, const int* supernode_of, char* nonzero);
template <int W>
void backward_avx2(const SupernodeView& s, double* y);

}  // namespace sinew
