#include "engine/math/transpose_columns.hpp"

#include <immintrin.h>

#include "engine/core/cpu_features.hpp"

namespace sinew {
namespace {

void transpose_scalar(const double* const* columns, int b0, int count, int d0, int height,
                      double* dst, long stride) {
  for (int b = b0; b < count; ++b)
    for (int d = d0; d < height; ++d) dst[d * stride + b] = columns[b][d];
}

// 4 x 4 tiles through registers: a column's 4 entries in one load, a row's 4 in one store
// (a store per entry and a strided walk otherwise).
__attribute__((target("avx2"))) void transpose_avx2(const double* const* columns, int count,
                                                    int height, double* dst, long stride) {
  const int full_b = count & ~3, full_d = height & ~3;
  for (int b = 0; b < full_b; b += 4) {
    const double *c0 = columns[b], *c1 = columns[b + 1], *c2 = columns[b + 2], *c3 = columns[b + 3];
    for (int d = 0; d < full_d; d += 4) {
      const __m256d r0 = _mm256_loadu_pd(c0 + d), r1 = _mm256_loadu_pd(c1 + d);
      const __m256d r2 = _mm256_loadu_pd(c2 + d), r3 = _mm256_loadu_pd(c3 + d);
      // (c0[d], c1[d], c0[d+2], c1[d+2]), (c0[d+1], c1[d+1], c0[d+3], c1[d+3]), likewise c2, c3
      const __m256d lo01 = _mm256_unpacklo_pd(r0, r1), hi01 = _mm256_unpackhi_pd(r0, r1);
      const __m256d lo23 = _mm256_unpacklo_pd(r2, r3), hi23 = _mm256_unpackhi_pd(r2, r3);
      double* out = dst + d * stride + b;
      _mm256_storeu_pd(out, _mm256_permute2f128_pd(lo01, lo23, 0x20));
      _mm256_storeu_pd(out + stride, _mm256_permute2f128_pd(hi01, hi23, 0x20));
      _mm256_storeu_pd(out + 2 * stride, _mm256_permute2f128_pd(lo01, lo23, 0x31));
      _mm256_storeu_pd(out + 3 * stride, _mm256_permute2f128_pd(hi01, hi23, 0x31));
    }
  }
  transpose_scalar(columns, 0, full_b, full_d, height, dst,
                   stride);  // the last rows of full tiles' columns
  transpose_scalar(columns, full_b, count, 0, height, dst, stride);  // the last columns
}

}  // namespace

void transpose_columns(const double* const* columns, int count, int height, double* dst,
                       long dst_stride) {
  if (use_avx2())
    transpose_avx2(columns, count, height, dst, dst_stride);
  else
    transpose_scalar(columns, 0, count, 0, height, dst, dst_stride);
}

}  // namespace sinew
