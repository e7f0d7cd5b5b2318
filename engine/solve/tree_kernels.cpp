#include "engine/solve/tree_kernels.hpp"

#include <algorithm>
#include <cstddef>

namespace sinew {

namespace {

// tree_kernels.hpp's dot product: four interleaved partial sums, then the rest in order.
template <class Real>
double dot(const Real* a, const double* b, int n) {
  double p[4] = {0, 0, 0, 0};
  const int whole = n & ~3;
  for (int i = 0; i < whole; i += 4)
    for (int j = 0; j < 4; ++j) p[j] += static_cast<double>(a[i + j]) * b[i + j];
  double total = (p[0] + p[1]) + (p[2] + p[3]);
  for (int i = whole; i < n; ++i) total += static_cast<double>(a[i]) * b[i];
  return total;
}

}  // namespace

template <class Real>
void tree_forward_rect_baseline(const BasicSupernodeView<Real>& s, const double* ys, int c0, int c1, int r0, int r1, double* x) {
  for (int k = c0; k < c1; ++k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height + r0;
    for (int r = 0; r < r1 - r0; ++r) x[r] -= static_cast<double>(column[r]) * ys[k];
  }
}

template <class Real>
void tree_forward_diagonal_baseline(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1) {
  for (int k = b0; k < b1; ++k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height;
    ys[k] /= static_cast<double>(column[k]);
    for (int r = k + 1; r < b1; ++r) ys[r] -= static_cast<double>(column[r]) * ys[k];
  }
}

template <class Real>
void tree_backward_rect_baseline(const BasicSupernodeView<Real>& s, const double* x, int r0, int r1, int c0, int c1, double* ys) {
  for (int k = c0; k < c1; ++k) ys[k] -= dot(s.L + static_cast<std::size_t>(k) * s.height + r0, x, r1 - r0);
}

template <class Real>
void tree_backward_diagonal_baseline(const BasicSupernodeView<Real>& s, double* ys, int b0, int b1) {
  for (int k = b1 - 1; k >= b0; --k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height;
    ys[k] = (ys[k] - dot(column + k + 1, ys + k + 1, b1 - 1 - k)) / static_cast<double>(column[k]);
  }
}

template void tree_forward_rect_baseline(const SupernodeView&, const double*, int, int, int, int, double*);
template void tree_forward_rect_baseline(const SingleSupernodeView&, const double*, int, int, int, int, double*);
template void tree_forward_diagonal_baseline(const SupernodeView&, double*, int, int);
template void tree_forward_diagonal_baseline(const SingleSupernodeView&, double*, int, int);
template void tree_backward_rect_baseline(const SupernodeView&, const double*, int, int, int, int, double*);
template void tree_backward_rect_baseline(const SingleSupernodeView&, const double*, int, int, int, int, double*);
template void tree_backward_diagonal_baseline(const SupernodeView&, double*, int, int);
template void tree_backward_diagonal_baseline(const SingleSupernodeView&, double*, int, int);

// The whole passes, from the pieces (AVX2 where the CPU has it).
template <class Real>
void tree_forward(const BasicSupernodeView<Real>& s, double* y, double* gather) {
  double* ys = y + s.first;
  tree_forward_diagonal(s, ys, 0, s.columns);
  if (s.height == s.columns) return;
  const int below = s.height - s.columns;
  for (int i = 0; i < below; ++i) gather[i] = y[s.rows[s.columns + i]];
  tree_forward_rect(s, ys, 0, s.columns, s.columns, s.height, gather);
  for (int i = 0; i < below; ++i) y[s.rows[s.columns + i]] = gather[i];
}

template <class Real>
void tree_backward(const BasicSupernodeView<Real>& s, double* y, double* gather) {
  double* ys = y + s.first;
  if (const int below = s.height - s.columns; below > 0) {
    for (int i = 0; i < below; ++i) gather[i] = y[s.rows[s.columns + i]];
    tree_backward_rect(s, gather, s.columns, s.height, 0, s.columns, ys);
  }
  if (!backward_in_blocks(s.columns)) {
    tree_backward_diagonal(s, ys, 0, s.columns);
    return;
  }
  for (int b0 = (s.columns - 1) / kTreeBlock * kTreeBlock; b0 >= 0; b0 -= kTreeBlock) {  // the header's blocks
    const int b1 = std::min(s.columns, b0 + kTreeBlock);
    if (b1 < s.columns) tree_backward_rect(s, ys + b1, b1, s.columns, b0, b1, ys);
    tree_backward_diagonal(s, ys, b0, b1);
  }
}

template void tree_forward(const SupernodeView&, double*, double*);
template void tree_forward(const SingleSupernodeView&, double*, double*);
template void tree_backward(const SupernodeView&, double*, double*);
template void tree_backward(const SingleSupernodeView&, double*, double*);

}  // namespace sinew
