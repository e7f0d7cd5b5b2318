#include "engine/constraints/lcp_pgs.hpp"

namespace sinew {

double lcp_residual(const MatX& W, const VecX& c, const RowTable& rows) {
  const int m = rows.size();
  const VecX lambda = Eigen::Map<const VecX>(rows.lambda.data(), m);
  const VecX w = W * lambda + c;
  double worst = 0;
  for (int i = 0; i < m; ++i) {
    double lo, hi;
    pgs_bounds(rows, lambda, i, lo, hi);
    // Natural residual: lambda - clamp(lambda - w / W_ii), measured back in units of w.
    const double projected = std::clamp(lambda[i] - w[i] / W(i, i), lo, hi);
    worst = std::max(worst, std::abs(lambda[i] - projected) * W(i, i));
  }
  return worst;
}

}  // namespace sinew
