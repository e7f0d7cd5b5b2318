#pragma once
// One supernode's passes of a single-column solve on a supernodal LL^T factor
// (supernodal_tree_solve.cpp), in a fixed order of operations, on the baseline build and in
// AVX2 with the same bits (no fused multiply-add; callers check use_avx2() first):
//   forward, L y = b: y_k /= L_kk, then the triangle's rows below k and the supernode's rows
//     below the triangle (through `gather`) take -L_rk y_k, column after column;
//   backward, L^T z = y: y_k -= the dot product of column k below the triangle with those
//     rows, then, last unknown first, y_k = (y_k - its dot product within the triangle) / L_kk.
// A dot product of n terms sums them in four interleaved partial sums p_j (terms j, j + 4,
// ... up to the last whole group of four), as (p_0 + p_1) + (p_2 + p_3), then the rest in order:
// four lanes of AVX2 where Eigen's kernels (which took these passes until 2026-12-06) used
// two. bunny_5's drop (one Newton iteration, 1 thread) spent a quarter of its time here.
// A single-precision view's values are widened to double as they are read: the arithmetic,
// and y, stay double, so the passes solve exactly (to double round-off) with the factor
// L~ of the rounded values, a fixed symmetric positive definite L~ L~^T, and read half
// the memory (the factor's values are most of what a pass reads).
#include "engine/solve/supernode_view.hpp"

namespace sinew {

template <class Real>
void tree_forward_baseline(const BasicSupernodeView<Real>& s, double* y, double* gather);
template <class Real>
void tree_backward_baseline(const BasicSupernodeView<Real>& s, double* y, double* gather);
template <class Real>
void tree_forward_avx2(const BasicSupernodeView<Real>& s, double* y, double* gather);
template <class Real>
void tree_backward_avx2(const BasicSupernodeView<Real>& s, double* y, double* gather);

}  // namespace sinew
