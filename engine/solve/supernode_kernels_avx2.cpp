#include "engine/solve/supernode_kernels_avx2.hpp"

#include <immintrin.h>

#include <cstddef>

// AVX2 for this file's functions alone (avx2_region_begin.hpp).
#include "engine/core/avx2_region_begin.hpp"

namespace sinew {

// Row r of the block: W values at y + W r (supernodal_block_solve.cpp). P registers a row.
template <int W>
void forward_avx2(const SupernodeView& s, double* y, const int* supernode_of,
                                                  char* nonzero) {
  static_assert(W % 4 == 0);
  constexpr int P = W / 4;
  // The triangle: y_k /= L_kk, then the rows below k within the triangle.
  for (int k = 0; k < s.columns; ++k) {
    const double* column = s.L + static_cast<std::size_t>(k) * s.height;
    double* yk = y + static_cast<std::size_t>(s.first + k) * W;
    const __m256d inverse = _mm256_set1_pd(1.0 / column[k]);
    __m256d v[P];
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) {
      v[p] = _mm256_mul_pd(_mm256_loadu_pd(yk + 4 * p), inverse);
      _mm256_storeu_pd(yk + 4 * p, v[p]);
    }
    for (int r = k + 1; r < s.columns; ++r) {
      double* yr = y + static_cast<std::size_t>(s.first + r) * W;
      const __m256d c = _mm256_set1_pd(column[r]);
      #pragma GCC unroll 4
      for (int p = 0; p < P; ++p)
        _mm256_storeu_pd(yr + 4 * p, _mm256_sub_pd(_mm256_loadu_pd(yr + 4 * p), _mm256_mul_pd(c, v[p])));
    }
  }
  // The rows below the triangle, two columns of L at a time.
  int k = 0;
  for (; k + 1 < s.columns; k += 2) {
    const double* c0 = s.L + static_cast<std::size_t>(k) * s.height;
    const double* c1 = c0 + s.height;
    const double* y0 = y + static_cast<std::size_t>(s.first + k) * W;
    const double* y1 = y0 + W;
    __m256d a[P], b[P];
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) a[p] = _mm256_loadu_pd(y0 + 4 * p), b[p] = _mm256_loadu_pd(y1 + 4 * p);
    for (int r = s.columns; r < s.height; ++r) {
      double* yr = y + static_cast<std::size_t>(s.rows[r]) * W;
      const __m256d l0 = _mm256_set1_pd(c0[r]), l1 = _mm256_set1_pd(c1[r]);
      #pragma GCC unroll 4
      for (int p = 0; p < P; ++p)
        _mm256_storeu_pd(yr + 4 * p, _mm256_sub_pd(_mm256_loadu_pd(yr + 4 * p),
                                                   _mm256_add_pd(_mm256_mul_pd(l0, a[p]), _mm256_mul_pd(l1, b[p]))));
    }
  }
  if (k < s.columns) {
    const double* c0 = s.L + static_cast<std::size_t>(k) * s.height;
    const double* y0 = y + static_cast<std::size_t>(s.first + k) * W;
    __m256d a[P];
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) a[p] = _mm256_loadu_pd(y0 + 4 * p);
    for (int r = s.columns; r < s.height; ++r) {
      double* yr = y + static_cast<std::size_t>(s.rows[r]) * W;
      const __m256d l0 = _mm256_set1_pd(c0[r]);
      #pragma GCC unroll 4
      for (int p = 0; p < P; ++p)
        _mm256_storeu_pd(yr + 4 * p, _mm256_sub_pd(_mm256_loadu_pd(yr + 4 * p), _mm256_mul_pd(l0, a[p])));
    }
  }
  for (int r = s.columns; r < s.height; ++r) nonzero[supernode_of[s.rows[r]]] = 1;
}

template <int W>
void backward_avx2(const SupernodeView& s, double* y) {
  static_assert(W % 4 == 0);
  constexpr int P = W / 4;
  // y_k -= sum over the rows below of L_rk y_r, two columns at a time.
  int k = 0;
  for (; k + 1 < s.columns; k += 2) {
    const double* c0 = s.L + static_cast<std::size_t>(k) * s.height;
    const double* c1 = c0 + s.height;
    __m256d a[P], b[P];
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) a[p] = _mm256_setzero_pd(), b[p] = _mm256_setzero_pd();
    for (int r = s.columns; r < s.height; ++r) {
      const double* yr = y + static_cast<std::size_t>(s.rows[r]) * W;
      const __m256d l0 = _mm256_set1_pd(c0[r]), l1 = _mm256_set1_pd(c1[r]);
      #pragma GCC unroll 4
      for (int p = 0; p < P; ++p) {
        const __m256d v = _mm256_loadu_pd(yr + 4 * p);
        a[p] = _mm256_add_pd(a[p], _mm256_mul_pd(l0, v));
        b[p] = _mm256_add_pd(b[p], _mm256_mul_pd(l1, v));
      }
    }
    double* y0 = y + static_cast<std::size_t>(s.first + k) * W;
    double* y1 = y0 + W;
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) {
      _mm256_storeu_pd(y0 + 4 * p, _mm256_sub_pd(_mm256_loadu_pd(y0 + 4 * p), a[p]));
      _mm256_storeu_pd(y1 + 4 * p, _mm256_sub_pd(_mm256_loadu_pd(y1 + 4 * p), b[p]));
    }
  }
  if (k < s.columns) {
    const double* c0 = s.L + static_cast<std::size_t>(k) * s.height;
    __m256d a[P];
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) a[p] = _mm256_setzero_pd();
    for (int r = s.columns; r < s.height; ++r) {
      const double* yr = y + static_cast<std::size_t>(s.rows[r]) * W;
      const __m256d l0 = _mm256_set1_pd(c0[r]);
      #pragma GCC unroll 4
      for (int p = 0; p < P; ++p) a[p] = _mm256_add_pd(a[p], _mm256_mul_pd(l0, _mm256_loadu_pd(yr + 4 * p)));
    }
    double* y0 = y + static_cast<std::size_t>(s.first + k) * W;
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) _mm256_storeu_pd(y0 + 4 * p, _mm256_sub_pd(_mm256_loadu_pd(y0 + 4 * p), a[p]));
  }
  // The triangle, transposed: last unknown first.
  for (int k = s.columns - 1; k >= 0; --k) {
    const double* column = s.L + static_cast<std::size_t>(k) * s.height;
    double* yk = y + static_cast<std::size_t>(s.first + k) * W;
    __m256d v[P];
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) v[p] = _mm256_loadu_pd(yk + 4 * p);
    for (int r = k + 1; r < s.columns; ++r) {
      const double* yr = y + static_cast<std::size_t>(s.first + r) * W;
      const __m256d c = _mm256_set1_pd(column[r]);
      #pragma GCC unroll 4
      for (int p = 0; p < P; ++p) v[p] = _mm256_sub_pd(v[p], _mm256_mul_pd(c, _mm256_loadu_pd(yr + 4 * p)));
    }
    const __m256d inverse = _mm256_set1_pd(1.0 / column[k]);
    #pragma GCC unroll 4
    for (int p = 0; p < P; ++p) _mm256_storeu_pd(yk + 4 * p, _mm256_mul_pd(v[p], inverse));
  }
}

template void forward_avx2<4>(const SupernodeView&, double*, const int*, char*);
template void forward_avx2<8>(const SupernodeView&, double*, const int*, char*);
template void forward_avx2<16>(const SupernodeView&, double*, const int*, char*);
template void backward_avx2<4>(const SupernodeView&, double*);
template void backward_avx2<8>(const SupernodeView&, double*);
template void backward_avx2<16>(const SupernodeView&, double*);

}  // namespace sinew

#include "engine/core/avx2_region_end.hpp"
