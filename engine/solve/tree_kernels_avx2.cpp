#include <immintrin.h>

#include <algorithm>
#include <cstddef>

#include "engine/solve/tree_kernels.hpp"

// AVX2 for this file's functions alone (avx2_region_begin.hpp).
#include "engine/core/avx2_region_begin.hpp"

namespace sinew {

namespace {

// (p_0 + p_1) + (p_2 + p_3) of four lanes.
double pair_sums(__m256d p) {
  const __m128d pairs = _mm_hadd_pd(_mm256_castpd256_pd128(p), _mm256_extractf128_pd(p, 1));  // (p0 + p1, p2 + p3)
  return _mm_cvtsd_f64(pairs) + _mm_cvtsd_f64(_mm_unpackhi_pd(pairs, pairs));
}

// Four values of L, widened to double when single.
__m256d load4(const double* a) { return _mm256_loadu_pd(a); }
__m256d load4(const float* a) { return _mm256_cvtps_pd(_mm_loadu_ps(a)); }

// tree_kernels.hpp's dot product: lane j holds p_j.
template <class Real>
double dot(const Real* a, const double* b, int n) {
  __m256d sum = _mm256_setzero_pd();
  const int whole = n & ~3;
  for (int i = 0; i < whole; i += 4) sum = _mm256_add_pd(sum, _mm256_mul_pd(load4(a + i), _mm256_loadu_pd(b + i)));
  double total = pair_sums(sum);
  for (int i = whole; i < n; ++i) total += static_cast<double>(a[i]) * b[i];
  return total;
}

// The dot products of columns a0 and a1 with b, b read once.
template <class Real>
void dot2(const Real* a0, const Real* a1, const double* b, int n, double& d0, double& d1) {
  __m256d s0 = _mm256_setzero_pd(), s1 = _mm256_setzero_pd();
  const int whole = n & ~3;
  for (int i = 0; i < whole; i += 4) {
    const __m256d v = _mm256_loadu_pd(b + i);
    s0 = _mm256_add_pd(s0, _mm256_mul_pd(load4(a0 + i), v));
    s1 = _mm256_add_pd(s1, _mm256_mul_pd(load4(a1 + i), v));
  }
  d0 = pair_sums(s0), d1 = pair_sums(s1);
  for (int i = whole; i < n; ++i) d0 += static_cast<double>(a0[i]) * b[i], d1 += static_cast<double>(a1[i]) * b[i];
}

// The dot products of columns a[0..3] with b, b read once; four independent sums.
template <class Real>
void dot4(const Real* const a[4], const double* b, int n, double d[4]) {
  __m256d s0 = _mm256_setzero_pd(), s1 = _mm256_setzero_pd(), s2 = _mm256_setzero_pd(), s3 = _mm256_setzero_pd();
  const int whole = n & ~3;
  for (int i = 0; i < whole; i += 4) {
    const __m256d v = _mm256_loadu_pd(b + i);
    s0 = _mm256_add_pd(s0, _mm256_mul_pd(load4(a[0] + i), v));
    s1 = _mm256_add_pd(s1, _mm256_mul_pd(load4(a[1] + i), v));
    s2 = _mm256_add_pd(s2, _mm256_mul_pd(load4(a[2] + i), v));
    s3 = _mm256_add_pd(s3, _mm256_mul_pd(load4(a[3] + i), v));
  }
  d[0] = pair_sums(s0), d[1] = pair_sums(s1), d[2] = pair_sums(s2), d[3] = pair_sums(s3);
  for (int i = whole; i < n; ++i)
    for (int j = 0; j < 4; ++j) d[j] += static_cast<double>(a[j][i]) * b[i];
}

// x[i] -= c[i] * v over n entries, four at a time.
template <class Real>
void subtract_scaled(double* x, const Real* c, double v, int n) {
  const __m256d scale = _mm256_set1_pd(v);
  int i = 0;
  for (; i + 4 <= n; i += 4)
    _mm256_storeu_pd(x + i, _mm256_sub_pd(_mm256_loadu_pd(x + i), _mm256_mul_pd(load4(c + i), scale)));
  for (; i < n; ++i) x[i] -= static_cast<double>(c[i]) * v;
}

// x[i] = (x[i] - c0[i] v0) - c1[i] v1: two columns' steps, x read and written once.
template <class Real>
void subtract_scaled2(double* x, const Real* c0, double v0, const Real* c1, double v1, int n) {
  const __m256d s0 = _mm256_set1_pd(v0), s1 = _mm256_set1_pd(v1);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d once = _mm256_sub_pd(_mm256_loadu_pd(x + i), _mm256_mul_pd(load4(c0 + i), s0));
    _mm256_storeu_pd(x + i, _mm256_sub_pd(once, _mm256_mul_pd(load4(c1 + i), s1)));
  }
  for (; i < n; ++i) x[i] = (x[i] - static_cast<double>(c0[i]) * v0) - static_cast<double>(c1[i]) * v1;
}

// x[i] = (((x[i] - c0[i] v0) - c1[i] v1) - c2[i] v2) - c3[i] v3: four columns' steps.
template <class Real>
void subtract_scaled4(double* x, const Real* const c[4], const double v[4], int n) {
  const __m256d s0 = _mm256_set1_pd(v[0]), s1 = _mm256_set1_pd(v[1]), s2 = _mm256_set1_pd(v[2]), s3 = _mm256_set1_pd(v[3]);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    __m256d r = _mm256_sub_pd(_mm256_loadu_pd(x + i), _mm256_mul_pd(load4(c[0] + i), s0));
    r = _mm256_sub_pd(r, _mm256_mul_pd(load4(c[1] + i), s1));
    r = _mm256_sub_pd(r, _mm256_mul_pd(load4(c[2] + i), s2));
    _mm256_storeu_pd(x + i, _mm256_sub_pd(r, _mm256_mul_pd(load4(c[3] + i), s3)));
  }
  for (; i < n; ++i)
    x[i] = (((x[i] - static_cast<double>(c[0][i]) * v[0]) - static_cast<double>(c[1][i]) * v[1]) -
            static_cast<double>(c[2][i]) * v[2]) - static_cast<double>(c[3][i]) * v[3];
}

}  // namespace

template <class Real>
void tree_forward_rect_avx2(const BasicSupernodeView<Real>& s, const double* ys, int c0, int c1, int r0, int r1, double* x) {
  const auto column = [&](int k) { return s.L + static_cast<std::size_t>(k) * s.height + r0; };
  const int n = r1 - r0;
  int k = c0;
  for (; k + 3 < c1; k += 4) {
    const Real* const c[4] = {column(k), column(k + 1), column(k + 2), column(k + 3)};
    subtract_scaled4(x, c, ys + k, n);
  }
  for (; k + 1 < c1; k += 2) subtract_scaled2(x, column(k), ys[k], column(k + 1), ys[k + 1], n);
  if (k < c1) subtract_scaled(x, column(k), ys[k], n);
}

template <class Real>
void tree_forward_diagonal_avx2(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1) {
  for (int k = b0; k < b1; ++k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height;
    ys[k] /= static_cast<double>(column[k]);
    subtract_scaled(ys + k + 1, column + k + 1, ys[k], b1 - 1 - k);
  }
}

template <class Real>
void tree_backward_rect_avx2(const BasicSupernodeView<Real>& s, const double* x, int r0, int r1, int c0, int c1, double* ys) {
  const auto column = [&](int k) { return s.L + static_cast<std::size_t>(k) * s.height + r0; };
  const int n = r1 - r0;
  int k = c0;
  for (; k + 3 < c1; k += 4) {
    const Real* const c[4] = {column(k), column(k + 1), column(k + 2), column(k + 3)};
    double d[4];
    dot4(c, x, n, d);
    for (int j = 0; j < 4; ++j) ys[k + j] -= d[j];
  }
  for (; k + 1 < c1; k += 2) {
    double d0, d1;
    dot2(column(k), column(k + 1), x, n, d0, d1);
    ys[k] -= d0, ys[k + 1] -= d1;
  }
  if (k < c1) ys[k] -= dot(column(k), x, n);
}

template <class Real>
void tree_backward_diagonal_avx2(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1) {
  for (int k = b1 - 1; k >= b0; --k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height;
    ys[k] = (ys[k] - dot(column + k + 1, ys + k + 1, b1 - 1 - k)) / static_cast<double>(column[k]);
  }
}

template void tree_forward_rect_avx2(const SupernodeView&, const double*, int, int, int, int, double*);
template void tree_forward_rect_avx2(const SingleSupernodeView&, const double*, int, int, int, int, double*);
template void tree_forward_diagonal_avx2(const SupernodeView&, double*, int, int);
template void tree_forward_diagonal_avx2(const SingleSupernodeView&, double*, int, int);
template void tree_backward_rect_avx2(const SupernodeView&, const double*, int, int, int, int, double*);
template void tree_backward_rect_avx2(const SingleSupernodeView&, const double*, int, int, int, int, double*);
template void tree_backward_diagonal_avx2(const SupernodeView&, double*, int, int);
template void tree_backward_diagonal_avx2(const SingleSupernodeView&, double*, int, int);

}  // namespace sinew

#include "engine/core/avx2_region_end.hpp"
