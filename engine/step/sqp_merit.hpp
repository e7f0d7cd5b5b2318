#pragma once
// The merit function of the SQP line search (solve_constraints.cpp): an l1 exact penalty
//   phi(v) = f(v) - g^T (v - v_k) + sum_i mu_kind(i) violation_i(x0 + h v) / h
// with f(v) = 1/2 v^T A v - b^T v the step's objective and g = J_f^T lambda_f the friction
// impulse of the last QP, held fixed (friction has no potential; with its impulse frozen the
// QP's step is still a descent direction of phi). violation is max(0, -C) for a unilateral
// row, |C| for an attachment; friction rows have none. lambda is an impulse and C / h a
// velocity, so each term is an energy like f. Once every mu exceeds its rows' |lambda| the
// penalty is exact (a local minimiser of phi solves the constrained problem), and with H
// positive definite the QP's step is a descent direction of phi.
#include <algorithm>
#include <array>
#include <cmath>

#include "engine/constraints/row_table.hpp"
#include "engine/model.hpp"

namespace sinew {

struct SqpMerit {
  std::array<double, kRowKindCount> weight{};  // mu per kind; only grows within a step

  // Twice the largest |lambda| of each kind: exact with a margin, as the next QP's
  // multipliers differ from these.
  void raise_weights(const RowTable& rows) {
    for (int i = 0; i < rows.size(); ++i)
      if (rows.kind[i] != RowKind::Friction) {
        double& mu = weight[static_cast<int>(rows.kind[i])];
        mu = std::max(mu, 2 * std::abs(rows.lambda[i]));
      }
  }

  // sum_i mu_i violation_i / h over the rows (C at their linearisation point). Rows not in
  // the table are at least their activation margin inside their limits: no violation.
  double penalty(const RowTable& rows, double h) const {
    return penalty_shifted(rows, h, [](int) { return 0.0; });
  }
  // The same at the rows' linearisation moved by J d (jd[i] = J_i d): C_i + h J_i d.
  double penalty_along(const RowTable& rows, const Eigen::Ref<const VecX>& jd, double h) const {
    return penalty_shifted(rows, h, [&](int i) { return h * jd[i]; });
  }

 private:
  template <typename Shift>
  double penalty_shifted(const RowTable& rows, double h, Shift shift) const {
    double sum = 0;
    for (int i = 0; i < rows.size(); ++i) {
      const RowKind kind = rows.kind[i];
      if (kind == RowKind::Friction) continue;
      const double value = rows.value[i] + shift(i);
      const double violation = kind == RowKind::Attachment ? std::abs(value) : std::max(0.0, -value);
      sum += weight[static_cast<int>(kind)] * violation;
    }
    return sum / h;
  }
};

// One QP step d from v_k, for the line search. f is quadratic, so its change along d is
// exact from two numbers, without evaluating f (and its cancellation) at each trial point.
struct MeritStep {
  double slope = 0;         // (A v_k - b)^T d - g^T d: the objective's part, to first order
  double curvature = 0;     // d^T A d
  double penalty_from = 0;  // the penalty at v_k
  double penalty_to = 0;    // the penalty of the linearised rows at v_k + d: 0 for the QP's own
                            // step (the LCP meets them), not for a conjugated one

  // Over the full step: slope + penalty_to - penalty_from (the linearised rows' penalty at
  // v_k + d, 0 when the QP met them). A descent
  // (< 0) whenever the LCP is solved, H is positive definite and every weight is at least
  // its rows' |lambda| (then it is at most -d^T H d).
  double predicted_change() const { return slope + penalty_to - penalty_from; }
  // The first step length to try. With rows that carry no curvature (contacts, friction,
  // attachments) the Lagrangian L(v) = f(v) - lambda^T C is quadratic with Hessian A, and
  // -lagrangian_slope / curvature is its exact minimiser along d. The QP steps with an
  // earlier step's factorisation (H != A) overshoot A's stiffer modes: every correction
  // ends about 1/0.75 past that minimiser (the resting creature), and the iteration
  // shrinks them only 3x per QP. Starting there removes the overshoot; otherwise 1.
  // Damping never moves the fixed point (d = 0 at a solution).
  static double first_trial(bool rows_linear, double lagrangian_slope, double curvature) {
    if (!rows_linear || !(curvature > 0)) return 1;
    const double minimiser = -lagrangian_slope / curvature;
    return minimiser > 0 && minimiser < 2 ? minimiser : 1;
  }
  // phi(v_k + alpha d) - phi(v_k), given the penalty at v_k + alpha d.
  double change(double alpha, double penalty_at) const {
    return alpha * slope + 0.5 * alpha * alpha * curvature + penalty_at - penalty_from;
  }
};

// g^T d = sum over friction rows of lambda_i J_i d (d on the free DOFs).
inline double friction_work(const Model& model, const RowTable& rows, const VecX& d) {
  double work = 0;
  for (int i = 0; i < rows.size(); ++i) {
    if (rows.kind[i] != RowKind::Friction) continue;
    for (int k = rows.begin[i]; k < rows.begin[i + 1]; ++k)
      if (const int f = model.free_index[rows.nodes[k]]; f >= 0) work += rows.lambda[i] * rows.jac[k].dot(d.segment<3>(3 * f));
  }
  return work;
}

}  // namespace sinew
