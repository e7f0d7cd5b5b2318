#pragma once
// The 16 3 x 3 blocks of an invariant material's tet Hessian (invariant_tet_hessian.hpp) formed
// and scattered into a system's values with AVX2, a block column in one register (lane 3
// unused): the same operations entry by entry as the scalar path, in the same order (no fused
// multiply-add), so the same bits. As there, the blocks (a, b) of nodes 1-3 are formed for
// a <= b and the others are their transposes (a register transpose: the same numbers).
#include "engine/assembly/tet_hessian_scatter.hpp"

namespace sinew {

// Per tet, the terms of block (a, b) of nodes 1-3 (invariant_tet_hessian.cpp's names), vectors
// of node a as [a][r] with r = 3 a zero pad:
//   K_ab = su_a u_b^T + sz_a z_b^T + diagonal_ab I + c_cross [cross_ab]x - sum_m sp_ma p_mb^T
// (su_a = c_f u_a, sz_a = c_cofactor z_a, sp_ma = w value_m p_ma), each product taken as
// (scaled entry of a) * (entry of b), the terms added in that order.
struct alignas(32) InvariantTetBlockTerms {
  double su[3][4], u[3][4], sz[3][4], z[3][4];
  double diagonal[3][3];          // [a][b], a <= b
  double cross_matrix[3][3][4];   // [pair][column] of [F (dN_a x dN_b)]x, pairs (0,1), (0,2), (1,2)
  double c_cross = 0;
  int modes = 0;
  double sp[9][3][4], p[9][3][4];
};

// Adds the tet's blocks into `to` (fixed nodes' blocks skipped). Call only when use_avx2().
void scatter_invariant_tet_blocks_avx2(const InvariantTetBlockTerms& terms, const TetHessianScatter& to);

}  // namespace sinew
