#include "engine/constraints/lcp_pgs.hpp"

namespace sinew {

double lcp_residual(const MatX& W, const VecX& c, const RowTable& rows, const VecX* weight) {
  const int m = rows.size();
  const VecX lambda = Eigen::Map<const VecX>(rows.lambda.data(), m);
  const VecX w = W * lambda + c;
  double worst = 0;
  for (int i = 0; i < m; ++i) {
    if (!(W(i, i) > 0)) continue;
    double lo, hi;
    pgs_bounds(rows, lambda, i, lo, hi);
    worst = std::max(worst, natural_residual(lambda[i], w[i], W(i, i), lo, hi) * (weight ? (*weight)[i] : 1.0));
  }
  return worst;
}

}  // namespace sinew
