#include "engine/assembly/kept_tet_hessians.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cmath>

#include "engine/core/cpu_features.hpp"

namespace sinew {

void KeptTetHessians::prepare(int elements, int pattern_entries, double h2) {
  if (static_cast<int>(F.size()) == elements && entries == pattern_entries && coeff == h2) return;
  coeff = h2;
  entries = pattern_entries;
  F.assign(elements, Mat3::Zero());
  kept.assign(elements, 0);
  blocks.clear();  // sized by allocate_blocks, once some element is known to keep its Hessian
  fresh.assign(elements, 0);
  values.clear();
  formed = 0;
  every_element_kept = any_element_kept = -1;
}

void KeptTetHessians::allocate_blocks() {
  blocks.resize(F.size());
  values.assign(static_cast<size_t>(std::max(entries, 0)), 0.0);
}

void KeptTetHessians::clear() {
  entries = -1;
  F.clear();
  kept.clear();
  blocks.clear();
  fresh.clear();
  values.clear();
  formed = 0;
  every_element_kept = any_element_kept = -1;
}

bool KeptTetHessians::needs_forming(int e, const Mat3& at, double tolerance) const {
  if (!kept[e]) return true;
  return !((at - F[e]).cwiseAbs().maxCoeff() <= tolerance);  // NaN: formed afresh
}

namespace {

void add_kept_differences(double* values, const double* formed, const double* held, const int* at) {
  for (int i = 0; i < 48; ++i) {
    if (at[i] < 0) continue;
    for (int r = 0; r < 3; ++r) values[at[i] + r] += formed[3 * i + r] - held[3 * i + r];
  }
}

// The same three at a time under a mask (the fourth value, another column's, untouched):
// the same operations, the same bits.
__attribute__((target("avx2"))) void add_kept_differences_avx2(double* values, const double* formed,
                                                          const double* held, const int* at) {
  const __m256i three = _mm256_set_epi64x(0, -1, -1, -1);
  for (int i = 0; i < 48; ++i) {
    if (at[i] < 0) continue;
    double* value = values + at[i];
    const __m256d difference =
        _mm256_sub_pd(_mm256_maskload_pd(formed + 3 * i, three), _mm256_maskload_pd(held + 3 * i, three));
    _mm256_maskstore_pd(value, three, _mm256_add_pd(_mm256_maskload_pd(value, three), difference));
  }
}

// The largest magnitudes of two blocks' 144 values, four lanes at a time: max is exact, so
// the order does not matter, and a NaN is passed over as by the scalar loop's std::max
// (_mm256_max_pd returns its second operand, the running maximum, when one is NaN).
__attribute__((target("avx2"))) void largest_magnitudes_avx2(const double* held, const double* formed,
                                                        double& largest_held, double& largest_formed) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d h = _mm256_setzero_pd(), f = _mm256_setzero_pd();
  for (int i = 0; i < 144; i += 4) {
    h = _mm256_max_pd(_mm256_andnot_pd(sign, _mm256_loadu_pd(held + i)), h);
    f = _mm256_max_pd(_mm256_andnot_pd(sign, _mm256_loadu_pd(formed + i)), f);
  }
  alignas(32) double lanes_h[4], lanes_f[4];
  _mm256_store_pd(lanes_h, h);
  _mm256_store_pd(lanes_f, f);
  largest_held = std::max({lanes_h[0], lanes_h[1], lanes_h[2], lanes_h[3]});
  largest_formed = std::max({lanes_f[0], lanes_f[1], lanes_f[2], lanes_f[3]});
}

}  // namespace

bool KeptTetHessians::replace(int e, const Mat3& at_F, const std::array<double, 144>& formed, const int* at) {
  std::array<double, 144>& held = blocks[e];
  if (!kept[e]) held.fill(0.0);
  // Blocks 1e4 times smaller than those they replace leave the sum with the large ones'
  // round-off, 1e4 u ~ 2e-12 of the new entries or more: summed anew after the pass.
  double largest_held = 0, largest_formed = 0;
  if (use_avx2()) {
    largest_magnitudes_avx2(held.data(), formed.data(), largest_held, largest_formed);
    add_kept_differences_avx2(values.data(), formed.data(), held.data(), at);
  } else {
    for (int i = 0; i < 144; ++i)
      largest_held = std::max(largest_held, std::abs(held[i])), largest_formed = std::max(largest_formed, std::abs(formed[i]));
    add_kept_differences(values.data(), formed.data(), held.data(), at);
  }
  held = formed;
  F[e] = at_F;
  kept[e] = 1;
  return largest_held > 1e4 * largest_formed;
}

void KeptTetHessians::rebuild(const std::vector<int>& element_scatter, const std::vector<int>& scatter_begin) {
  std::fill(values.begin(), values.end(), 0.0);
  for (size_t e = 0; e < kept.size(); ++e) {
    if (!kept[e]) continue;
    const int* at = element_scatter.data() + scatter_begin[e];
    for (int i = 0; i < 48; ++i) {
      if (at[i] < 0) continue;
      for (int r = 0; r < 3; ++r) values[at[i] + r] += blocks[e][3 * i + r];
    }
  }
}

}  // namespace sinew
