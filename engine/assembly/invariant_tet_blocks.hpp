#pragma once
// The 16 3 x 3 blocks of an invariant material's tet Hessian (invariant_tet_hessian.hpp) formed
// and scattered into a system's values with AVX2, a block column in one register (lane 3
// unused): the same operations entry by entry as the scalar path, in the same order (no fused
// multiply-add), so the same bits. As there, the blocks (a, b) of nodes 1-3 are formed for
// a <= b and the others are their transposes (a register transpose: the same numbers).
#include "engine/assembly/tet_hessian_scatter.hpp"
#include "engine/fem/hex8.hpp"
#include "engine/materials/eigen_projection.hpp"

namespace sinew {

// M d with each entry summed left to right, (M_r0 d_0 + M_r1 d_1) + M_r2 d_2: the order of the
// AVX2 path's columns (a register per column of M), spelt out in the scalar path too rather
// than left to Eigen's product evaluator, whose order is its own to choose (the bits did not
// change when this replaced it).
inline Vec3 times(const Mat3& M, const Vec3& d) {
  Vec3 out;
  for (int r = 0; r < 3; ++r) out[r] = (M(r, 0) * d[0] + M(r, 1) * d[1]) + M(r, 2) * d[2];
  return out;
}

// Per tet, the terms of block (a, b) of nodes 1-3 (invariant_tet_hessian.cpp's names), vectors
// of node a as [a][r] with r = 3 a zero pad:
//   K_ab = su_a u_b^T + sz_a z_b^T + diagonal_ab I + c_cross [cross_ab]x - sum_m sp_ma p_mb^T
// (su_a = c_f u_a, sz_a = c_cofactor z_a, sp_ma = w value_m p_ma), each product taken as
// (scaled entry of a) * (entry of b), the terms added in that order.
// Rows of 4 doubles start on 32-byte boundaries (aligned AVX loads and stores).
struct InvariantTetBlockTerms {
  alignas(32) double su[3][4];
  alignas(32) double u[3][4];
  alignas(32) double sz[3][4];
  alignas(32) double z[3][4];
  alignas(32) double cross_matrix[3][3][4];  // [pair][column] of [F (dN_a x dN_b)]x, pairs (0,1), (0,2), (1,2)
  alignas(32) double sp[9][3][4];
  alignas(32) double p[9][3][4];
  double diagonal[3][3];  // [a][b], a <= b
  double c_cross = 0;
  int modes = 0;
};

// The vectors of nodes 1-3 (u, z, su, sz, p, sp above) for dN's rows 1-3, F's cofactor and
// the first terms.modes of `modes`, by times() and products with the coefficients. Call only
// when use_avx2().
void fill_node_vectors_avx2(const Mat3& F, const Mat3& cofactor, const Mat83& dN, const NegativeModes& modes,
                            double w, double c_f, double c_cofactor, InvariantTetBlockTerms& terms);

// Adds the tet's blocks into `to` (fixed nodes' blocks skipped). Call only when use_avx2().
void scatter_invariant_tet_blocks_avx2(const InvariantTetBlockTerms& terms, const TetHessianScatter& to);

}  // namespace sinew
