// The SQP line search's merit function (engine/step/sqp_merit.hpp): its penalty counts each
// row's violation by its kind (none for friction, |C| for attachments), its weights follow
// the multipliers, and the friction work is lambda^T J d over friction rows only. Along a
// QP step, MeritStep's change equals phi evaluated directly, and its predicted change is a
// descent of at least d^T A d when the weights exceed the multipliers.
#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "engine/constraints/lcp_pgs.hpp"
#include "engine/step/sqp_merit.hpp"

using namespace sinew;

namespace {

// Two nodes, node 1 fixed.
Model two_node_model() {
  Model m;
  m.num_nodes = 2;
  m.free_index = {0, -1};
  m.num_free = 1;
  return m;
}

void add_row(RowTable& rows, RowKind kind, double value, double lambda, const Vec3& j0, const Vec3& j1) {
  rows.add_row(kind, value, kind == RowKind::Attachment || kind == RowKind::Friction ? -1e300 : 0.0, 1e300, 0);
  rows.add_entry(0, j0);
  rows.add_entry(1, j1);
  rows.lambda.back() = lambda;
}

}  // namespace

TEST_CASE("sqp merit: the penalty weighs each kind's violation, friction none") {
  RowTable rows;
  add_row(rows, RowKind::Strain, -0.002, 0.5, Vec3::UnitX(), Vec3::Zero());      // violated by 0.002
  add_row(rows, RowKind::Strain, 0.004, 0.0, Vec3::UnitY(), Vec3::Zero());       // met: no violation
  add_row(rows, RowKind::Contact, -0.01, 3.0, Vec3::UnitZ(), Vec3::Zero());      // 0.01 m inside
  add_row(rows, RowKind::Attachment, 0.25, -4.0, Vec3::UnitX(), Vec3::Zero());   // gap either way
  add_row(rows, RowKind::Friction, -7.0, 1.5, Vec3::UnitY(), Vec3::Zero());      // has no violation
  SqpMerit merit;
  merit.raise_weights(rows);
  CHECK(merit.weight[static_cast<int>(RowKind::Strain)] == 1.0);      // 2 x 0.5
  CHECK(merit.weight[static_cast<int>(RowKind::Contact)] == 6.0);     // 2 x 3
  CHECK(merit.weight[static_cast<int>(RowKind::Attachment)] == 8.0);  // 2 x |-4|
  CHECK(merit.weight[static_cast<int>(RowKind::Friction)] == 0.0);
  const double h = 0.01;
  CHECK(merit.penalty(rows, h) == doctest::Approx((1.0 * 0.002 + 6.0 * 0.01 + 8.0 * 0.25) / h).epsilon(1e-15));

  // Weights only grow within a step.
  for (double& l : rows.lambda) l *= 0.1;
  merit.raise_weights(rows);
  CHECK(merit.weight[static_cast<int>(RowKind::Contact)] == 6.0);
}

TEST_CASE("sqp merit: the friction work is lambda^T J d over friction rows, free nodes only") {
  const Model model = two_node_model();
  RowTable rows;
  add_row(rows, RowKind::Friction, 0, 2.0, Vec3(1, 2, 3), Vec3(100, 100, 100));  // node 1 fixed: ignored
  add_row(rows, RowKind::Contact, 0, 5.0, Vec3(1, 1, 1), Vec3::Zero());          // not friction: ignored
  add_row(rows, RowKind::Friction, 0, -0.5, Vec3(0, 1, 0), Vec3::Zero());
  const VecX d = Vec3(0.1, -0.2, 0.3);
  CHECK(friction_work(model, rows, d) == doctest::Approx(2.0 * (0.1 - 0.4 + 0.9) - 0.5 * (-0.2)).epsilon(1e-15));
}

TEST_CASE("sqp merit: with linear constraints a QP step's predicted change is exact and a descent") {
  // min 1/2 v^T A v - b^T v  s.t.  C_i(v) = c_i + h g_i^T v >= 0, from v_k; one free node
  // (3 DOFs), three rows: the QP of solve_constraints with exact linearisation, solved by
  // PGS on W = J A^-1 J^T.
  const Model model = two_node_model();
  const double h = 0.02;
  Mat3 A;
  A << 4, 1, 0, 1, 3, 0.5, 0, 0.5, 2;
  const Vec3 b(1, -2, 0.5), v_k(0.3, 0.1, -0.2);
  const Vec3 g[3] = {Vec3(1, 0, 0), Vec3(0.6, 0.8, 0), Vec3(0, -0.3, 1)};
  // Newton step of the objective, then the LCP for the rows: v = v_base + A^-1 J^T lambda.
  const Vec3 v_base = A.ldlt().solve(b);
  // C at v = 0, chosen so that rows 0 and 2 are violated at v_base, row 1 is not.
  const double over[3] = {0.004, -0.001, 0.002};
  double c0[3];
  for (int i = 0; i < 3; ++i) c0[i] = -h * g[i].dot(v_base) - over[i];
  RowTable rows;
  for (int i = 0; i < 3; ++i) add_row(rows, RowKind::Strain, c0[i] + h * g[i].dot(v_k), 0.0, g[i], Vec3::Zero());
  MatX J(3, 3), W;
  for (int i = 0; i < 3; ++i) J.row(i) = g[i].transpose();
  W = J * A.inverse() * J.transpose();
  VecX c(3), weight = VecX::Ones(3);
  for (int i = 0; i < 3; ++i) c[i] = rows.value[i] / h + g[i].dot(v_base - v_k);
  DenseLcpMatrix lcp(W);
  solve_pgs(lcp, c, weight, rows, 10000, 1e-14);
  REQUIRE(rows.lambda[0] + rows.lambda[2] > 0);  // the violated rows carry force: complementarity is exercised
  Vec3 v_next = v_base;
  for (int i = 0; i < 3; ++i) v_next += A.inverse() * g[i] * rows.lambda[i];
  const Vec3 d = v_next - v_k;

  SqpMerit merit;
  merit.raise_weights(rows);
  MeritStep step;  // as solve_constraints fills it (no friction rows here)
  step.slope = (A * v_k - b).dot(d) - friction_work(model, rows, d);
  step.curvature = d.dot(A * d);
  step.penalty_from = merit.penalty(rows, h);
  REQUIRE(step.penalty_from > 0);  // v_k violates rows 0 and 2

  // phi evaluated directly, f and the rows at v_k + alpha d.
  const auto phi = [&](double alpha) {
    const Vec3 v = v_k + alpha * d;
    RowTable at;
    for (int i = 0; i < 3; ++i) add_row(at, RowKind::Strain, c0[i] + h * g[i].dot(v), 0.0, g[i], Vec3::Zero());
    return std::make_pair(0.5 * v.dot(A * v) - b.dot(v) + merit.penalty(at, h), merit.penalty(at, h));
  };
  const auto [phi_0, penalty_0] = phi(0);
  CHECK(penalty_0 == step.penalty_from);
  for (const double alpha : {1.0, 0.5, 0.125}) {
    const auto [phi_alpha, penalty_alpha] = phi(alpha);
    CHECK(step.change(alpha, penalty_alpha) == doctest::Approx(phi_alpha - phi_0).epsilon(1e-9));
  }
  // At v_k + d every row holds (to PGS's 1e-14): the penalty is gone, and the change is the
  // prediction plus the curvature term.
  const double penalty_1 = phi(1).second;
  CHECK(penalty_1 <= 1e-10 * step.penalty_from);
  CHECK(step.change(1, penalty_1) == doctest::Approx(step.predicted_change() + 0.5 * d.dot(A * d)).epsilon(1e-9));
  // A descent of at least d^T A d: the weights (2 |lambda|) exceed the multipliers.
  CHECK(step.predicted_change() <= -d.dot(A * d) * (1 - 1e-9));
}
