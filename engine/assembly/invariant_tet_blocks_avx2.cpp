#include "engine/assembly/invariant_tet_blocks.hpp"

#include <immintrin.h>

namespace sinew {

// Named, not anonymous: the file is compiled in a unity batch, whose files share one
// anonymous namespace.
namespace invariant_tet_blocks_detail {

// target("avx2") without "fma": no contraction of x * a + y into one rounding.
#define SINEW_AVX2 __attribute__((target("avx2"), always_inline)) inline

// Lane c set, the others clear: where block column c holds its diagonal entry.
alignas(32) constexpr long long kDiagonalLane[3][4] = {{-1, 0, 0, 0}, {0, -1, 0, 0}, {0, 0, -1, 0}};

struct Block {
  __m256d column[3];
};

// Block (a, b) of nodes 1-3, a <= b; pair: its cross term's index when a < b.
SINEW_AVX2 Block form_block(const InvariantTetBlockTerms& t, int a, int b, int pair) {
  const __m256d su = _mm256_load_pd(t.su[a]), sz = _mm256_load_pd(t.sz[a]);
  const __m256d diagonal = _mm256_set1_pd(t.diagonal[a][b]), c_cross = _mm256_set1_pd(t.c_cross);
  Block block;
  for (int c = 0; c < 3; ++c) {
    __m256d column = _mm256_add_pd(_mm256_mul_pd(su, _mm256_broadcast_sd(&t.u[b][c])),
                                   _mm256_mul_pd(sz, _mm256_broadcast_sd(&t.z[b][c])));
    const __m256d lane = _mm256_castsi256_pd(_mm256_load_si256(reinterpret_cast<const __m256i*>(kDiagonalLane[c])));
    column = _mm256_blendv_pd(column, _mm256_add_pd(column, diagonal), lane);
    if (pair >= 0) column = _mm256_add_pd(column, _mm256_mul_pd(c_cross, _mm256_load_pd(t.cross_matrix[pair][c])));
    for (int m = 0; m < t.modes; ++m)
      column = _mm256_sub_pd(column, _mm256_mul_pd(_mm256_load_pd(t.sp[m][a]), _mm256_broadcast_sd(&t.p[m][b][c])));
    block.column[c] = column;
  }
  return block;
}

// The transpose (lane 3 of each column: zero).
SINEW_AVX2 Block transposed(const Block& k) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d t0 = _mm256_unpacklo_pd(k.column[0], k.column[1]), t1 = _mm256_unpackhi_pd(k.column[0], k.column[1]);
  const __m256d t2 = _mm256_unpacklo_pd(k.column[2], zero), t3 = _mm256_unpackhi_pd(k.column[2], zero);
  return {{_mm256_permute2f128_pd(t0, t2, 0x20), _mm256_permute2f128_pd(t1, t3, 0x20),
           _mm256_permute2f128_pd(t0, t2, 0x31)}};
}

// -(x + y + z), added left to right.
SINEW_AVX2 Block negated_sum(const Block& x, const Block& y, const Block& z) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  Block sum;
  for (int c = 0; c < 3; ++c)
    sum.column[c] = _mm256_xor_pd(_mm256_add_pd(_mm256_add_pd(x.column[c], y.column[c]), z.column[c]), sign);
  return sum;
}

// values[column[d] + r] += coeff * block(r, d), as add_tet_block: three lanes loaded and
// stored under a mask (the fourth value, another block's, is not touched).
SINEW_AVX2 void scatter_block(const TetHessianScatter& to, int a, int b, const Block& block) {
  const int* column = to.positions + 3 * (4 * a + b);
  if (column[0] < 0) return;  // a fixed node
  const __m256d coeff = _mm256_set1_pd(to.coeff);
  const __m256i rows = _mm256_set_epi64x(0, -1, -1, -1);
  for (int d = 0; d < 3; ++d) {
    double* value = to.values + column[d];
    _mm256_maskstore_pd(value, rows,
                        _mm256_add_pd(_mm256_maskload_pd(value, rows), _mm256_mul_pd(coeff, block.column[d])));
  }
}

// times(M, d) for the columns of M, d's entries broadcast: (c0 d0 + c1 d1) + c2 d2.
SINEW_AVX2 __m256d times_columns(const double* M, __m256d d0, __m256d d1, __m256d d2) {
  const __m256i rows = _mm256_set_epi64x(0, -1, -1, -1);
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_maskload_pd(M, rows), d0),
                                     _mm256_mul_pd(_mm256_maskload_pd(M + 3, rows), d1)),
                       _mm256_mul_pd(_mm256_maskload_pd(M + 6, rows), d2));
}

}  // namespace invariant_tet_blocks_detail

using namespace invariant_tet_blocks_detail;

__attribute__((target("avx2"))) void fill_node_vectors_avx2(const Mat3& F, const Mat3& cofactor, const Mat83& dN,
                                                            const NegativeModes& modes, double w, double c_f,
                                                            double c_cofactor, InvariantTetBlockTerms& t) {
  const __m256d scale_u = _mm256_set1_pd(c_f), scale_z = _mm256_set1_pd(c_cofactor);
  for (int a = 0; a < 3; ++a) {
    const __m256d d0 = _mm256_set1_pd(dN(a + 1, 0)), d1 = _mm256_set1_pd(dN(a + 1, 1)), d2 = _mm256_set1_pd(dN(a + 1, 2));
    const __m256d u = times_columns(F.data(), d0, d1, d2), z = times_columns(cofactor.data(), d0, d1, d2);
    _mm256_store_pd(t.u[a], u);
    _mm256_store_pd(t.z[a], z);
    _mm256_store_pd(t.su[a], _mm256_mul_pd(scale_u, u));
    _mm256_store_pd(t.sz[a], _mm256_mul_pd(scale_z, z));
    for (int m = 0; m < t.modes; ++m) {
      const __m256d p = times_columns(modes.matrices[m].data(), d0, d1, d2);
      _mm256_store_pd(t.p[m][a], p);
      _mm256_store_pd(t.sp[m][a], _mm256_mul_pd(_mm256_set1_pd(w * modes.values[m]), p));
    }
  }
}

__attribute__((target("avx2"))) void scatter_invariant_tet_blocks_avx2(const InvariantTetBlockTerms& t,
                                                                       const TetHessianScatter& to) {
  Block K[3][3];
  K[0][0] = form_block(t, 0, 0, -1);
  K[1][1] = form_block(t, 1, 1, -1);
  K[2][2] = form_block(t, 2, 2, -1);
  K[0][1] = form_block(t, 0, 1, 0);
  K[0][2] = form_block(t, 0, 2, 1);
  K[1][2] = form_block(t, 1, 2, 2);
  K[1][0] = transposed(K[0][1]);
  K[2][0] = transposed(K[0][2]);
  K[2][1] = transposed(K[1][2]);
  // K_0b = -(K_1b + K_2b + K_3b) (the shape function gradients sum to zero), K_00 = -sum_b K_0b.
  Block K0[3];
  for (int b = 0; b < 3; ++b) K0[b] = negated_sum(K[0][b], K[1][b], K[2][b]);
  scatter_block(to, 0, 0, negated_sum(K0[0], K0[1], K0[2]));
  for (int b = 0; b < 3; ++b) {
    scatter_block(to, 0, b + 1, K0[b]);
    scatter_block(to, b + 1, 0, transposed(K0[b]));
    for (int a = 0; a < 3; ++a) scatter_block(to, a + 1, b + 1, K[a][b]);
  }
}

#undef SINEW_AVX2

}  // namespace sinew
