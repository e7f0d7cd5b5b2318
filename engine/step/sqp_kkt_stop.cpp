#include "engine/step/sqp_kkt_stop.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/constraints/lcp_pgs.hpp"

namespace sinew {

bool last_multipliers_solve(const RowTable& last_qp, const RowTable& rows, double h, const SolverDesc& cfg,
                            std::vector<std::pair<uint64_t, int>>& last_rows, std::vector<double>& lambda) {
  last_rows.clear();
  for (int j = 0; j < last_qp.size(); ++j) last_rows.emplace_back(last_qp.key[j], j);
  std::sort(last_rows.begin(), last_rows.end());
  const int m = rows.size();
  lambda.assign(m, 0.0);
  int carried = 0;  // rows of `rows` given a nonzero multiplier of the last QP
  for (int i = 0; i < m; ++i) {
    const auto it = std::lower_bound(last_rows.begin(), last_rows.end(), std::make_pair(rows.key[i], -1));
    if (it == last_rows.end() || it->first != rows.key[i]) continue;  // a new row: multiplier 0
    const int j = it->second;
    const int count = rows.begin[i + 1] - rows.begin[i];
    if (count != last_qp.begin[j + 1] - last_qp.begin[j] ||
        std::memcmp(&rows.nodes[rows.begin[i]], &last_qp.nodes[last_qp.begin[j]], count * sizeof(int)) != 0 ||
        std::memcmp(rows.jac[rows.begin[i]].data(), last_qp.jac[last_qp.begin[j]].data(), count * sizeof(Vec3)) != 0)
      return false;
    lambda[i] = last_qp.lambda[j];
    if (lambda[i] != 0) ++carried;
  }
  // A row gone with its force: J^T lambda would no longer balance the residual.
  if (carried != std::count_if(last_qp.lambda.begin(), last_qp.lambda.end(), [](double l) { return l != 0; }))
    return false;
  for (int i = 0; i < m; ++i) {
    double lo, hi;
    pgs_bounds(rows, lambda, i, lo, hi);
    const double l = lambda[i], w = rows.value[i] / h;
    if (!(l >= lo && l <= hi) || !std::isfinite(w)) return false;  // NaN fails too
    const double residual = lo == hi   ? 0.0  // a friction row of a contact without force: no freedom
                            : l == lo  ? std::max(0.0, -w)
                            : l == hi  ? std::max(0.0, w)
                                       : std::abs(w);
    if (!(residual * h / row_tolerance(cfg, rows.kind[i]) <= cfg.pgs_tolerance)) return false;
  }
  return true;
}

}  // namespace sinew
