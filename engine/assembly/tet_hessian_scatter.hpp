#pragma once
// Where a tet's 12 x 12 Hessian goes: a matrix, or straight into the values of a matrix with
// the system pattern (system_pattern.hpp), times a coefficient, at the element's scatter
// positions. The second skips forming the 12 x 12 matrix, zeroing it and reading it back in
// scatter_element_matrix (~1,300 instructions a tet in the bunny_5 assembly), with the same
// sums bit for bit: each value receives one product coeff * entry per element either way,
// and the system's values are never -0 (they start at +0 or a mass), so an entry's zero sign
// (0 - s in the matrix against -s here) cannot show.
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "engine/core/types.hpp"

namespace sinew {

struct TetHessianScatter {
  const int* positions = nullptr;  // the element's 48 scatter positions (SystemPattern::element_scatter)
  double coeff = 1;
  double* values = nullptr;
};

// Adds the 3 x 3 block (a, b), a, b in 0-3, of a tet's Hessian (a matrix of 12 rows or more).
template <class Matrix>
void add_tet_block(Matrix& hessian, int a, int b, const Mat3& block) {
  hessian.template block<3, 3>(3 * a, 3 * b) += block;
}

// A block column's three values lie together in the system's values, as in the block: rows 0-1
// in one SSE2 operation, each entry still values + coeff * entry, the same bits (the bunny_5
// pass, callgrind: add_tet_blocks ~920 -> ~740 instructions a tet).
inline void add_tet_block(const TetHessianScatter& to, int a, int b, const Mat3& block) {
  const int* column = to.positions + 3 * (4 * a + b);
  if (column[0] < 0) return;  // a fixed node
#if defined(__SSE2__)
  const __m128d coeff = _mm_set1_pd(to.coeff);
  for (int d = 0; d < 3; ++d) {
    double* value = to.values + column[d];
    const double* entry = block.data() + 3 * d;
    _mm_storeu_pd(value, _mm_add_pd(_mm_loadu_pd(value), _mm_mul_pd(coeff, _mm_loadu_pd(entry))));
    value[2] += to.coeff * entry[2];
  }
#else
  for (int d = 0; d < 3; ++d)
    for (int r = 0; r < 3; ++r) to.values[column[d] + r] += to.coeff * block(r, d);
#endif
}

// The 16 blocks of a tet's Hessian from those of nodes 1-3 (K[a - 1][b - 1]) and node 0's
// row K0[b - 1] = K_0b (the shape function gradients sum to zero: K_0b = -sum_a K_ab and
// K_00 = -sum_b K_0b).
template <class Sink>
void add_tet_blocks(const Mat3 (&K)[3][3], const Mat3 (&K0)[3], Sink& hessian) {
  add_tet_block(hessian, 0, 0, -(K0[0] + K0[1] + K0[2]));
  for (int b = 0; b < 3; ++b) {
    add_tet_block(hessian, 0, b + 1, K0[b]);
    add_tet_block(hessian, b + 1, 0, K0[b].transpose());
    for (int a = 0; a < 3; ++a) add_tet_block(hessian, a + 1, b + 1, K[a][b]);
  }
}

}  // namespace sinew
