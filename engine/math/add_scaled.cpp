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

}  // namespace

void add_scaled(double* y, const double* x, double a, int n) {
  if (use_avx2())
    add_scaled_avx2(y, x, a, n);
  else  // Eigen's own loop (SSE2 in this build), as the callers wrote it before
    Eigen::Map<VecX>(y, n).noalias() += Eigen::Map<const VecX>(x, n) * a;
}

}  // namespace sinew
