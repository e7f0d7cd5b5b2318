#include "engine/solve/tree_kernels.hpp"

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
void tree_forward_baseline(const BasicSupernodeView<Real>& s, double* y, double* gather) {
  double* ys = y + s.first;
  const int below = s.height - s.columns;
  for (int i = 0; i < below; ++i) gather[i] = y[s.rows[s.columns + i]];
  for (int k = 0; k < s.columns; ++k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height;
    ys[k] /= static_cast<double>(column[k]);
    const double yk = ys[k];
    for (int r = k + 1; r < s.columns; ++r) ys[r] -= static_cast<double>(column[r]) * yk;
    for (int i = 0; i < below; ++i) gather[i] -= static_cast<double>(column[s.columns + i]) * yk;
  }
  for (int i = 0; i < below; ++i) y[s.rows[s.columns + i]] = gather[i];
}

template <class Real>
void tree_backward_baseline(const BasicSupernodeView<Real>& s, double* y, double* gather) {
  double* ys = y + s.first;
  const int below = s.height - s.columns;
  if (below > 0) {
    for (int i = 0; i < below; ++i) gather[i] = y[s.rows[s.columns + i]];
    for (int k = 0; k < s.columns; ++k)
      ys[k] -= dot(s.L + static_cast<std::size_t>(k) * s.height + s.columns, gather, below);
  }
  for (int k = s.columns - 1; k >= 0; --k) {
    const Real* column = s.L + static_cast<std::size_t>(k) * s.height;
    ys[k] = (ys[k] - dot(column + k + 1, ys + k + 1, s.columns - 1 - k)) / static_cast<double>(column[k]);
  }
}

template void tree_forward_baseline(const SupernodeView&, double*, double*);
template void tree_forward_baseline(const SingleSupernodeView&, double*, double*);
template void tree_backward_baseline(const SupernodeView&, double*, double*);
template void tree_backward_baseline(const SingleSupernodeView&, double*, double*);

}  // namespace sinew
