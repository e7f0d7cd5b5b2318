#include <immintrin.h>

#include "engine/math/jacobi_columns.hpp"

namespace sinew::detail {

namespace {

// Entry i of column j of B (or V) for four matrices, one per lane.
struct Lanes {
  __m256d b[3][3];
  __m256d v[3][3];
};

// target("avx2") without "fma": no contraction of x * a + y into one rounding, as in the
// scalar path.
__attribute__((target("avx2"))) inline __m256d dot3_lanes(const __m256d* x, const __m256d* y) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x[0], y[0]), _mm256_mul_pd(x[1], y[1])),
                       _mm256_mul_pd(x[2], y[2]));
}

// (x, y) <- (c x - s y, s x + c y) in the lanes of `mask`.
__attribute__((target("avx2"))) inline void rotate_lanes(__m256d* x, __m256d* y, __m256d c, __m256d s, __m256d mask) {
  for (int k = 0; k < 3; ++k) {
    const __m256d a = x[k], b = y[k];
    const __m256d x_new = _mm256_sub_pd(_mm256_mul_pd(c, a), _mm256_mul_pd(s, b));
    const __m256d y_new = _mm256_add_pd(_mm256_mul_pd(s, a), _mm256_mul_pd(c, b));
    x[k] = _mm256_blendv_pd(a, x_new, mask);
    y[k] = _mm256_blendv_pd(b, y_new, mask);
  }
}

// orthogonalize_pair (rotation_variant_svd.cpp), lane by lane; returns the lanes it rotated.
__attribute__((target("avx2"))) __m256d orthogonalize_lanes(Lanes& m, int p, int q) {
  const __m256d* bp = m.b[p];
  const __m256d* bq = m.b[q];
  const __m256d alpha = dot3_lanes(bp, bp), beta = dot3_lanes(bq, bq), gamma = dot3_lanes(bp, bq);
  const __m256d eps2 = _mm256_set1_pd(kOrthogonal * kOrthogonal);
  // gamma^2 > eps^2 alpha beta, as ((eps^2 alpha) beta)
  const __m256d skewed =
      _mm256_cmp_pd(_mm256_mul_pd(gamma, gamma), _mm256_mul_pd(_mm256_mul_pd(eps2, alpha), beta), _CMP_GT_OQ);
  const __m256d d = _mm256_sub_pd(beta, alpha);
  const __m256d abs_d = _mm256_andnot_pd(_mm256_set1_pd(-0.0), d);
  const __m256d four = _mm256_set1_pd(4.0), two = _mm256_set1_pd(2.0);
  const __m256d r =
      _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(d, d), _mm256_mul_pd(_mm256_mul_pd(four, gamma), gamma)));
  const __m256d r_plus = _mm256_add_pd(r, abs_d);
  const __m256d w = _mm256_sqrt_pd(_mm256_mul_pd(_mm256_mul_pd(two, r), r_plus));
  const __m256d mask = _mm256_and_pd(skewed, _mm256_cmp_pd(w, _mm256_setzero_pd(), _CMP_GT_OQ));
  const __m256d inverse_w = _mm256_div_pd(_mm256_set1_pd(1.0), w);
  const __m256d c = _mm256_mul_pd(r_plus, inverse_w);
  // d < 0 ? -2 gamma : 2 gamma (2 gamma negated exactly by its sign bit)
  const __m256d two_gamma = _mm256_mul_pd(two, gamma);
  const __m256d negative = _mm256_cmp_pd(d, _mm256_setzero_pd(), _CMP_LT_OQ);
  const __m256d signed_gamma = _mm256_blendv_pd(two_gamma, _mm256_xor_pd(two_gamma, _mm256_set1_pd(-0.0)), negative);
  const __m256d s = _mm256_mul_pd(signed_gamma, inverse_w);
  rotate_lanes(m.b[p], m.b[q], c, s, mask);
  rotate_lanes(m.v[p], m.v[q], c, s, mask);
  return mask;
}

}  // namespace

__attribute__((target("avx2"))) void jacobi_sweeps4_avx2(JacobiColumns* m) {
  Lanes lanes;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      lanes.b[j][i] = _mm256_setr_pd(m[0].b[j][i], m[1].b[j][i], m[2].b[j][i], m[3].b[j][i]);
      lanes.v[j][i] = _mm256_setr_pd(m[0].v[j][i], m[1].v[j][i], m[2].v[j][i], m[3].v[j][i]);
    }
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    __m256d rotated = orthogonalize_lanes(lanes, 0, 1);
    rotated = _mm256_or_pd(rotated, orthogonalize_lanes(lanes, 0, 2));
    rotated = _mm256_or_pd(rotated, orthogonalize_lanes(lanes, 1, 2));
    if (_mm256_movemask_pd(rotated) == 0) break;
  }
  alignas(32) double out[4];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      _mm256_store_pd(out, lanes.b[j][i]);
      for (int l = 0; l < 4; ++l) m[l].b[j][i] = out[l];
      _mm256_store_pd(out, lanes.v[j][i]);
      for (int l = 0; l < 4; ++l) m[l].v[j][i] = out[l];
    }
}

}  // namespace sinew::detail
