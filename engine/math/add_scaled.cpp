#include "engine/math/add_scaled.hpp"

#include <immintrin.h>

#include "engine/core/cpu_features.hpp"
#include "engine/core/types.hpp"

namespace sinew {
namespace {

// target("avx2") without "fma": the compiler may not contract x * a + y into one rounding.
__attribute__((target("avx2"))) void add_scaled_avx2(double* y, const double* x, double a, int n) {
  const __m256d scale = _mm256_set1_pd(a);
  int i = 0;
  for (; i + 4 <= n; i += 4)
    _mm256_storeu_pd(y + i, _mm256_add_pd(_mm256_loadu_pd(y + i), _mm256_mul_pd(_mm256_loadu_pd(x + i), scale)));
  for (; i < n; ++i) y[i] += x[i] * a;
}

// y += x0 a0, then += x1 a1, += x2 a2, += x3 a3: four add_scaled in one pass over y.
__attribute__((target("avx2"))) void add_scaled4_avx2(double* y, const double* const* x, const double* a, int n) {
  const __m256d s0 = _mm256_set1_pd(a[0]), s1 = _mm256_set1_pd(a[1]), s2 = _mm256_set1_pd(a[2]),
                s3 = _mm256_set1_pd(a[3]);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    __m256d sum = _mm256_add_pd(_mm256_loadu_pd(y + i), _mm256_mul_pd(_mm256_loadu_pd(x[0] + i), s0));
    sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_loadu_pd(x[1] + i), s1));
    sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_loadu_pd(x[2] + i), s2));
    _mm256_storeu_pd(y + i, _mm256_add_pd(sum, _mm256_mul_pd(_mm256_loadu_pd(x[3] + i), s3)));
  }
  for (; i < n; ++i) y[i] = (((y[i] + x[0][i] * a[0]) + x[1][i] * a[1]) + x[2][i] * a[2]) + x[3][i] * a[3];
}

// Accumulate: y += the sum; else y = the sum (no read of y: a column built from nothing).
template <bool Accumulate>
__attribute__((target("avx2"))) void scaled3_avx2(double* y, const double* x0, const double* x1, const double* x2,
                                                  double a0, double a1, double a2, int n) {
  const __m256d s0 = _mm256_set1_pd(a0), s1 = _mm256_set1_pd(a1), s2 = _mm256_set1_pd(a2);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(x0 + i), s0),
                                                    _mm256_mul_pd(_mm256_loadu_pd(x1 + i), s1)),
                                      _mm256_mul_pd(_mm256_loadu_pd(x2 + i), s2));
    _mm256_storeu_pd(y + i, Accumulate ? _mm256_add_pd(_mm256_loadu_pd(y + i), sum) : sum);
  }
  for (; i < n; ++i) {
    const double sum = (x0[i] * a0 + x1[i] * a1) + x2[i] * a2;
    y[i] = Accumulate ? y[i] + sum : sum;
  }
}

template <bool Accumulate>
void scaled3(double* y, const double* x0, const double* x1, const double* x2, double a0, double a1, double a2, int n) {
  if (use_avx2()) {
    scaled3_avx2<Accumulate>(y, x0, x1, x2, a0, a1, a2, n);
  } else {
    using Column = Eigen::Map<const VecX>;
    if (Accumulate)
      Eigen::Map<VecX>(y, n).noalias() += Column(x0, n) * a0 + Column(x1, n) * a1 + Column(x2, n) * a2;
    else
      Eigen::Map<VecX>(y, n).noalias() = Column(x0, n) * a0 + Column(x1, n) * a1 + Column(x2, n) * a2;
  }
}

}  // namespace

void add_scaled3(double* y, const double* x0, const double* x1, const double* x2, double a0, double a1, double a2,
                 int n) {
  scaled3<true>(y, x0, x1, x2, a0, a1, a2, n);
}

void set_scaled3(double* y, const double* x0, const double* x1, const double* x2, double a0, double a1, double a2,
                 int n) {
  scaled3<false>(y, x0, x1, x2, a0, a1, a2, n);
}

void add_scaled4(double* y, const double* const* x, const double* a, int n) {
  if (use_avx2()) {
    add_scaled4_avx2(y, x, a, n);
    return;
  }
  for (int k = 0; k < 4; ++k) add_scaled(y, x[k], a[k], n);  // the baseline path, column by column
}

void add_scaled(double* y, const double* x, double a, int n) {
  if (use_avx2())
    add_scaled_avx2(y, x, a, n);
  else  // Eigen's own loop (SSE2 in this build), as the callers wrote it before
    Eigen::Map<VecX>(y, n).noalias() += Eigen::Map<const VecX>(x, n) * a;
}

}  // namespace sinew
