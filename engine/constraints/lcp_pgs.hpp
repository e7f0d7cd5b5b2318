#pragma once
// Projected Gauss-Seidel for the boxed LCP of paper 000, eq. 23 (after [CPS92]):
//   find lambda with lo <= lambda <= hi and w = W lambda + c such that
//   lambda_i = lo_i => w_i >= 0,  lambda_i = hi_i => w_i <= 0,  otherwise w_i = 0.
// Friction rows take lo = -mu lambda_n, hi = +mu lambda_n from their normal row, updated
// as the sweep goes (a box approximation of the Coulomb cone, two rows per contact).
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/constraints/lcp_subspace.hpp"
#include "engine/constraints/row_table.hpp"

namespace sinew {

struct PgsResult {
  int iterations = 0;
  int subspace_products = 0;  // products with W taken by subspace steps (lcp_subspace.hpp)
  double residual = 0;  // largest weighted natural residual of the last sweep (see solve_pgs)
};

// Row i's multiplier bounds at the current lambda (friction rows follow their normal row).
// Rows: a RowTable, or any table with its lo, hi, normal_row and mu (lcp_active_set.hpp).
template <typename Rows, typename Lambda>
inline void pgs_bounds(const Rows& rows, const Lambda& lambda, int i, double& lo, double& hi) {
  const int n = rows.normal_row[i];
  if (n < 0) {
    lo = rows.lo[i], hi = rows.hi[i];
  } else {
    hi = rows.mu[i] * std::max(0.0, lambda[n]);
    lo = -hi;
  }
}

// Row i's natural residual |clamp(lambda_i - w_i / W_ii, lo, hi) - lambda_i| W_ii: 0 when the
// row meets its complementarity conditions, else how far, in the units of w.
inline double natural_residual(double lambda, double w, double diagonal, double lo, double hi) {
  return std::abs(std::clamp(lambda - w / diagonal, lo, hi) - lambda) * diagonal;
}

// An operator with entry(i, j) = W_ij, the very value changed(j, .) adds to w(i), and changed4
// (four changed() in one pass over w, the same operations on each value of w in the same
// order): solve_pgs takes its sweep's changes four at a time; the rows between read theirs as
// w_i plus the pending changes' terms, added in the order changed() would have added them, so
// every w_i read and the w after each sweep are bit for bit the one-at-a-time sweep's.
// (Delassus has an entry() but no changed4: its entries are formed, not those its changes add.)
template <typename Operator>
constexpr bool kDefersChanges = requires(Operator& op, const int* p, const double* d) {
  op.entry(0, 0);
  op.changed4(p, d);
};

// W given through an operator (delassus.hpp, or DenseLcpMatrix below) with
//   diagonal(i), start(lambda, c) (w = W lambda + c from scratch), w(i), changed(i, delta).
// W symmetric positive semi-definite with a positive diagonal. Starts from rows.lambda (warm
// start), clamped into the bounds; writes it back. A row that stays clamped (most inactive
// strain and contact rows) costs only w(i) per sweep; w is restarted from scratch every
// kRefresh sweeps against drift.
// Stops when, after a sweep, every row's natural residual
//   r_i = |clamp(lambda_i - w_i / W_ii, lo_i, hi_i) - lambda_i| W_ii
// (0 when row i meets its complementarity conditions; in the units of w) times weight_i is
// at most `tolerance`. It measures the constraints, not the multipliers: with redundant
// rows (more rows than DOFs: strain limits, contacts embedded in one element) W is
// singular and lambda may drift for long along its null space while w, and so the motion,
// has converged. Measured after the sweep, not during it: in a redundant set a row's own
// update is mostly undone by its neighbours', so the size of the updates says little.
// With subspace_interval > 0, every that many sweeps that leave the tolerance unmet are
// followed by a subspace step (lcp_subspace.hpp; W must then provide multiply_rows) of at most
// kSubspaceCg conjugate-gradient iterations.
// With an `offset` (m values), w = W (lambda - offset) + c: the LCP of c - W offset, whose
// products with W (W.start, from scratch) are taken of lambda - offset. A caller who knows w
// at a warm start equal to the offset passes it as c: the first start then costs no product
// with W (the first QP after the Newton predictor: w = C/h at lambda_0).
template <typename Operator, typename Rows>
PgsResult solve_pgs(Operator& W, const Eigen::Ref<const VecX>& c, const Eigen::Ref<const VecX>& weight,
                    Rows& rows, int max_iterations, double tolerance, int subspace_interval = 0,
                    const double* offset = nullptr) {
  // Subspace steps of 10 CG iterations: on paper 001's pressed finger, 20 cost more
  // products than the sweeps they save, 5 save too few.
  constexpr int kRefresh = 16, kSubspaceCg = 10;
  const int m = rows.size();
  Eigen::Map<VecX> lambda(rows.lambda.data(), m);  // solved in place
  PgsResult result;
  thread_local SubspaceScratch scratch;
  if (subspace_interval > 0) scratch.reserve(m);  // now, not at the first step that needs it
  thread_local std::vector<double> shifted;  // lambda - offset (kept: no allocation once warm)
  shifted.reserve(m);  // on every call: sized by the largest LCP of any kind, as scratch
  const auto start = [&] {
    if (!offset) return W.start(lambda, c);
    shifted.resize(m);
    for (int i = 0; i < m; ++i) shifted[i] = lambda[i] - offset[i];
    W.start(Eigen::Map<const VecX>(shifted.data(), m), c);
  };
  constexpr bool kDeferred = kDefersChanges<Operator>;
  int pending = 0;
  int pending_row[4];
  double pending_change[4];
  for (int it = 0; it < max_iterations; ++it) {
    if (it % kRefresh == 0) start();
    for (int i = 0; i < m; ++i) {
      if (!(W.diagonal(i) > 0)) continue;  // a row that moves no free DOF: nothing to solve
      double lo, hi;
      pgs_bounds(rows, lambda, i, lo, hi);
      double w = W.w(i);
      if constexpr (kDeferred)
        for (int k = 0; k < pending; ++k) w += W.entry(i, pending_row[k]) * pending_change[k];
      const double updated = std::clamp(lambda[i] - w / W.diagonal(i), lo, hi);
      if (const double change = updated - lambda[i]; change != 0) {
        lambda[i] = updated;
        if constexpr (kDeferred) {
          pending_row[pending] = i;
          pending_change[pending] = change;
          if (++pending == 4) W.changed4(pending_row, pending_change), pending = 0;
        } else {
          W.changed(i, change);
        }
      }
    }
    if constexpr (kDeferred) {
      for (int k = 0; k < pending; ++k) W.changed(pending_row[k], pending_change[k]);
      pending = 0;
    }
    result.iterations = it + 1;
    result.residual = 0;
    for (int i = 0; i < m; ++i) {
      if (!(W.diagonal(i) > 0)) continue;
      double lo, hi;
      pgs_bounds(rows, lambda, i, lo, hi);
      result.residual = std::max(result.residual, natural_residual(lambda[i], W.w(i), W.diagonal(i), lo, hi) * weight[i]);
    }
    if (result.residual <= tolerance) break;
    if (subspace_interval > 0 && (it + 1) % subspace_interval == 0 && it + 1 < max_iterations) {
      result.subspace_products += subspace_step(W, rows, lambda, kSubspaceCg, scratch);
      start();
    }
  }
  return result;
}

// A dense W as a solve_pgs operator.
class DenseLcpMatrix {
 public:
  explicit DenseLcpMatrix(const MatX& W) : m_W(W) {}
  double diagonal(int i) const { return m_W(i, i); }
  void start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c) { m_w.noalias() = m_W * lambda + c; }
  double w(int i) const { return m_w[i]; }
  void changed(int i, double delta) { m_w.noalias() += m_W.col(i) * delta; }  // symmetric: column = row
  void multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> out) const {
    principal_block_product(m_W, rows, x, out);
  }

 private:
  const MatX& m_W;
  VecX m_w;
};

// With unit weights: the tolerance is in the units of w.
inline PgsResult solve_pgs(const MatX& W, const VecX& c, RowTable& rows, int max_iterations, double tolerance) {
  DenseLcpMatrix op(W);
  return solve_pgs(op, c, VecX::Ones(rows.size()), rows, max_iterations, tolerance);
}

// Largest violation of the LCP conditions at lambda (0 at an exact solution), in the
// units of w, each row's times its weight (none: 1), rows with W_ii = 0 left out as
// solve_pgs leaves them; for tests and diagnostics.
double lcp_residual(const MatX& W, const VecX& c, const RowTable& rows, const VecX* weight = nullptr);

}  // namespace sinew
