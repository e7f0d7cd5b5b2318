#include "engine/constraints/lcp_pgs.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {
namespace {

void bounds_of(const RowTable& rows, const VecX& lambda, int i, double& lo, double& hi) {
  const int n = rows.normal_row[i];
  if (n < 0) {
    lo = rows.lo[i], hi = rows.hi[i];
  } else {
    hi = rows.mu[i] * std::max(0.0, lambda[n]);
    lo = -hi;
  }
}

}  // namespace

// w = W lambda + c is kept up to date as lambda changes (a column update per change), so a
// row that stays clamped (most inactive strain and contact rows) costs O(1) per sweep
// instead of O(m). w is recomputed from scratch every kRefresh sweeps against drift.
PgsResult solve_pgs(const MatX& W, const VecX& c, RowTable& rows, int max_iterations, double tolerance) {
  constexpr int kRefresh = 16;
  const int m = rows.size();
  VecX lambda = Eigen::Map<const VecX>(rows.lambda.data(), m);
  VecX w(m);
  PgsResult result;
  for (int it = 0; it < max_iterations; ++it) {
    if (it % kRefresh == 0) w.noalias() = W * lambda + c;
    double largest_change = 0, largest = 0;
    for (int i = 0; i < m; ++i) {
      double lo, hi;
      bounds_of(rows, lambda, i, lo, hi);
      const double updated = std::clamp(lambda[i] - w[i] / W(i, i), lo, hi);
      const double change = updated - lambda[i];
      if (change != 0) {
        w += W.col(i) * change;  // W symmetric: column i = row i
        lambda[i] = updated;
      }
      largest_change = std::max(largest_change, std::abs(change));
      largest = std::max(largest, std::abs(updated));
    }
    result.iterations = it + 1;
    result.change = largest > 0 ? largest_change / largest : largest_change;
    if (result.change <= tolerance) break;
  }
  std::copy(lambda.data(), lambda.data() + m, rows.lambda.begin());
  return result;
}

double lcp_residual(const MatX& W, const VecX& c, const RowTable& rows) {
  const int m = rows.size();
  const VecX lambda = Eigen::Map<const VecX>(rows.lambda.data(), m);
  const VecX w = W * lambda + c;
  double worst = 0;
  for (int i = 0; i < m; ++i) {
    double lo, hi;
    bounds_of(rows, lambda, i, lo, hi);
    // Natural residual: lambda - clamp(lambda - w / W_ii), measured back in units of w.
    const double projected = std::clamp(lambda[i] - w[i] / W(i, i), lo, hi);
    worst = std::max(worst, std::abs(lambda[i] - projected) * W(i, i));
  }
  return worst;
}

}  // namespace sinew
