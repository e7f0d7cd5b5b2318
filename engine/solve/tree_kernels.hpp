#pragma once
// One supernode's passes of a single-column solve on a supernodal LL^T factor
// (supernodal_tree_solve.cpp), in a fixed order of operations, on the baseline build and in
// AVX2 with the same bits (no fused multiply-add; use_avx2() picks, in the dispatchers below):
//   forward, L y = b: y_k /= L_kk, then the triangle's rows below k and the supernode's rows
//     below the triangle (through `gather`) take -L_rk y_k, column after column;
//   backward, L^T z = y: y_k -= the dot product of column k below the triangle with those
//     rows, then (a wide supernode's: below) the triangle in blocks, last block first, else,
//     last unknown first, y_k = (y_k - its dot product within the triangle) / L_kk.
// A dot product of n terms sums them in four interleaved partial sums p_j (terms j, j + 4,
// ... up to the last whole group of four), as (p_0 + p_1) + (p_2 + p_3), then the rest in order:
// four lanes of AVX2 where Eigen's kernels (which took these passes until 2026-12-06) used
// two. bunny_5's drop (one Newton iteration, 1 thread) spent a quarter of its time here.
// A single-precision view's values are widened to double as they are read: the arithmetic,
// and y, stay double, so the passes solve exactly (to double round-off) with the factor
// L~ of the rounded values, a fixed symmetric positive definite L~ L~^T, and read half
// the memory (the factor's values are most of what a pass reads).
#include "engine/core/cpu_features.hpp"
#include "engine/solve/supernode_view.hpp"

namespace sinew {

// The backward pass of a wide supernode (at least four blocks of kTreeBlock columns) in
// blocks, last block first: column k of block J (columns b0 = J T .. b1 - 1) takes its
// triangle's dot product in two pieces, y_k -= the dot product over the triangle's rows after
// the block (b1 and on), then, last unknown of the block first, y_k = (y_k - the dot product
// over the block's own rows below k) / L_kk. A narrower supernode takes one dot product per
// column over its whole triangle, as every supernode did before 2026-12-07. The blocks let two
// threads share a wide supernode's triangle with the bits of one (wide_supernode_passes.hpp),
// and give the long dot products four columns at a time (four independent chains of
// additions instead of one per column). The forward pass needs no such change: each entry
// takes its columns' steps in order, however they are grouped. Wide supernodes are the top
// separators of large factors (cube_20: a 936-column root); the rule depends on the factor
// alone, so the bits do not depend on the thread count.
inline constexpr int kTreeBlock = 64;
// From four blocks: a narrower triangle's passes take a few microseconds, about what waking
// the second thread costs, and its bits stay as they were (the paper scenes' factors).
inline bool backward_in_blocks(int columns) { return columns >= 4 * kTreeBlock; }

// The whole passes (tree_kernels.cpp, from the pieces below; AVX2 where the CPU has it).
template <class Real>
void tree_forward(const BasicSupernodeView<Real>& s, double* y, double* gather);
template <class Real>
void tree_backward(const BasicSupernodeView<Real>& s, double* y, double* gather);

// Pieces of the passes, ys = y + s.first (the triangle's unknowns), rows and columns of the
// supernode (rows from 0: the triangle's, then those below it):
//   forward_rect: x[r - r0] -= L_rk ys[k] for rows r0 <= r < r1, columns c0 <= k < c1 in
//     order (r0 >= c1; x the rows' values: ys + r0 in the triangle, the gather buffer below);
//   forward_diagonal: the triangle's rows and columns b0 <= k < b1 alone, as above;
//   backward_rect: ys[k] -= the dot product of L_rk and x[r - r0] over r0 <= r < r1, for
//     columns c0 <= k < c1 (r0 >= c1);
//   backward_diagonal: last unknown first, ys[k] = (ys[k] - the dot product of L_rk and ys[r]
//     over k < r < b1) / L_kk for b0 <= k < b1.
template <class Real>
void tree_forward_rect_baseline(const BasicSupernodeView<Real>& s, const double* ys, int c0, int c1, int r0, int r1, double* x);
template <class Real>
void tree_forward_diagonal_baseline(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1);
template <class Real>
void tree_backward_rect_baseline(const BasicSupernodeView<Real>& s, const double* x, int r0, int r1, int c0, int c1, double* ys);
template <class Real>
void tree_backward_diagonal_baseline(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1);
template <class Real>
void tree_forward_rect_avx2(const BasicSupernodeView<Real>& s, const double* ys, int c0, int c1, int r0, int r1, double* x);
template <class Real>
void tree_forward_diagonal_avx2(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1);
template <class Real>
void tree_backward_rect_avx2(const BasicSupernodeView<Real>& s, const double* x, int r0, int r1, int c0, int c1, double* ys);
template <class Real>
void tree_backward_diagonal_avx2(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1);

// The pieces, AVX2 where the CPU has it.
template <class Real>
void tree_forward_rect(const BasicSupernodeView<Real>& s, const double* ys, int c0, int c1, int r0, int r1, double* x) {
  if (use_avx2()) tree_forward_rect_avx2(s, ys, c0, c1, r0, r1, x);
  else tree_forward_rect_baseline(s, ys, c0, c1, r0, r1, x);
}
template <class Real>
void tree_forward_diagonal(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1) {
  if (use_avx2()) tree_forward_diagonal_avx2(s, ys, b0, b1);
  else tree_forward_diagonal_baseline(s, ys, b0, b1);
}
template <class Real>
void tree_backward_rect(const BasicSupernodeView<Real>& s, const double* x, int r0, int r1, int c0, int c1, double* ys) {
  if (use_avx2()) tree_backward_rect_avx2(s, x, r0, r1, c0, c1, ys);
  else tree_backward_rect_baseline(s, x, r0, r1, c0, c1, ys);
}
template <class Real>
void tree_backward_diagonal(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1) {
  if (use_avx2()) tree_backward_diagonal_avx2(s, ys, b0, b1);
  else tree_backward_diagonal_baseline(s, ys, b0, b1);
}

}  // namespace sinew
