#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <limits>
#include <random>
#include <vector>

#include "engine/constraints/lcp_pgs.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

// A random SPD matrix with a dominant diagonal (PGS converges for any SPD W; the
// diagonal dominance just keeps the iteration count small for the test).
MatX random_spd(int m, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  MatX B(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) B(i, j) = normal(rng);
  return B * B.transpose() + m * MatX::Identity(m, m);
}

}  // namespace

TEST_CASE("PGS converges to an LCP solution: residual falls with the iterations") {
  std::mt19937 rng(7);
  const int m = 30;
  const MatX W = random_spd(m, rng);
  std::normal_distribution<double> normal;
  VecX c(m);
  for (int i = 0; i < m; ++i) c[i] = normal(rng);
  double previous = 1e300;
  for (int iterations : {1, 5, 20, 200}) {
    RowTable rows;
    for (int i = 0; i < m; ++i) rows.add_row(RowKind::Energy, 0, 0, 1e300, i);
    solve_pgs(W, c, rows, iterations, 0);
    const double residual = lcp_residual(W, c, rows);
    MESSAGE(iterations << " sweeps: LCP residual " << residual);
    CHECK(residual <= previous);
    previous = residual;
    for (double l : rows.lambda) CHECK(l >= 0);
  }
  CHECK(previous < 1e-10 * c.norm());
}

TEST_CASE("PGS: friction rows stay inside the Coulomb box of their normal row") {
  std::mt19937 rng(3);
  const int contacts = 6;
  const MatX W = random_spd(3 * contacts, rng);
  VecX c(3 * contacts);
  RowTable rows;
  for (int k = 0; k < contacts; ++k) {
    const int n = rows.add_row(RowKind::Contact, 0, 0, 1e300, 3 * k);
    c[n] = -1.0;  // approaching: needs a push
    for (int t = 0; t < 2; ++t) {
      const int r = rows.add_row(RowKind::Friction, 0, 0, 0, 3 * k + 1 + t);
      rows.normal_row[r] = n;
      rows.mu[r] = 0.3;
      c[r] = 5.0 * (t ? 1 : -1);  // strong sliding: friction saturates
    }
  }
  solve_pgs(W, c, rows, 500, 1e-12);
  for (int k = 0; k < contacts; ++k) {
    const double ln = rows.lambda[3 * k];
    CHECK(ln > 0);
    for (int t = 1; t <= 2; ++t) CHECK(std::abs(rows.lambda[3 * k + t]) <= 0.3 * ln * (1 + 1e-12));
  }
  CHECK(lcp_residual(W, c, rows) < 1e-8);
}

TEST_CASE("PGS warm start from the solution stops after one sweep") {
  std::mt19937 rng(11);
  const MatX W = random_spd(10, rng);
  const VecX c = -VecX::Ones(10);
  RowTable rows;
  for (int i = 0; i < 10; ++i) rows.add_row(RowKind::Energy, 0, 0, 1e300, i);
  solve_pgs(W, c, rows, 1000, 1e-14);
  CHECK(solve_pgs(W, c, rows, 1000, 1e-10).iterations == 1);
}

namespace {

// Subspace steps (lcp_subspace.hpp).

// W = J G J^T with more rows than DOFs (singular, like strain limits: 18 rows per tet on
// 12 DOFs) and G the inverse of a chain's Laplacian (stiffness k) plus a unit mass (a wide
// spectrum, as for a soft body's H^-1): the case subspace steps are for.
MatX redundant_delassus(int rows, int dofs, std::mt19937& rng, double k) {
  MatX H = MatX::Zero(dofs, dofs);
  for (int i = 0; i + 1 < dofs; ++i) {
    H(i, i) += k, H(i + 1, i + 1) += k;
    H(i, i + 1) -= k, H(i + 1, i) -= k;
  }
  H.diagonal().array() += 1.0;
  const MatX G = H.inverse();
  std::normal_distribution<double> normal;
  MatX J = MatX::Zero(rows, dofs);
  for (int r = 0; r < rows; ++r)  // each row on three neighbouring DOFs, as a stencil
    for (int k = 0; k < 3; ++k) J(r, (r + k) % dofs) = normal(rng);
  return J * G * J.transpose();
}

// c for which lambda* (> 0 on every other row, 0 elsewhere) solves the LCP with w = s
// (0 where lambda* > 0, > 0 elsewhere): a solvable problem, as a physical one is. (With a
// singular W a random c may admit no lambda >= 0 at all; PGS then runs off.)
VecX solvable_c(const MatX& W, std::mt19937& rng, VecX& solution) {
  std::uniform_real_distribution<double> uniform(0.5, 1.5);
  const int m = static_cast<int>(W.rows());
  solution = VecX::Zero(m);
  VecX slack = VecX::Zero(m);
  for (int i = 0; i < m; ++i) (i % 2 ? slack[i] : solution[i]) = uniform(rng);
  return slack - W * solution;
}

RowTable unilateral_rows(int m) {
  RowTable rows;
  for (int i = 0; i < m; ++i) rows.add_row(RowKind::Strain, 0, 0, 1e300, i);
  return rows;
}

}  // namespace

TEST_CASE("a subspace step with the right free set lands on the LCP solution") {
  // An interior solution lambda* > 0 (w = 0 at every row): every row is free, and CG on
  // the 8 x 8 W_FF is exact within its 10 iterations.
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  MatX B(8, 8);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) B(i, j) = normal(rng);
  const MatX W = B * B.transpose() + MatX::Identity(8, 8);
  VecX solution(8);
  for (int i = 0; i < 8; ++i) solution[i] = 1.0 + 0.1 * i;
  const VecX c = -W * solution;
  RowTable rows = unilateral_rows(8);
  for (int i = 0; i < 8; ++i) rows.lambda[i] = 0.5;
  DenseLcpMatrix op(W);
  Eigen::Map<VecX> lambda(rows.lambda.data(), 8);
  op.start(lambda, c);
  const VecX D = W.diagonal();
  const auto reduced = [&](const VecX& w) { return w.dot(w.cwiseQuotient(D)); };  // w^T D^-1 w
  const double before = reduced(W * lambda + c);
  SubspaceScratch scratch;
  subspace_step(op, rows, lambda, 10, scratch);
  // CG ran until r^T D^-1 r fell by kSubspaceCgReduction (or to its exact end at 8
  // iterations, r = 0), and the truncation at a bound never fired (lambda* is interior and
  // the path from 0.5 stays positive): the residual meets that reduction, and the error
  // follows from it, |lambda - lambda*| <= |W^-1| |w|.
  const VecX w = W * lambda + c;
  CHECK(reduced(w) <= kSubspaceCgReduction * before * (1 + 1e-9));
  const double inverse_norm = 1 / test::min_eigenvalue(W);
  CHECK((lambda - solution).norm() <= inverse_norm * w.norm() * (1 + 1e-9) + 1e-14 * solution.norm());
  for (int i = 0; i < 8; ++i) CHECK(lambda[i] > 0);
}

TEST_CASE("a subspace step leaves friction rows and rows on a bound alone, and lowers the LCP's quadratic") {
  std::mt19937 rng(9);
  const MatX W = redundant_delassus(12, 9, rng, 1e3);
  VecX solution;
  const VecX c = solvable_c(W, rng, solution);
  RowTable rows = unilateral_rows(10);
  for (int t = 0; t < 2; ++t) {
    const int r = rows.add_row(RowKind::Friction, 0, 0, 0, 10 + t);
    rows.normal_row[r] = 0;
    rows.mu[r] = 0.5;
  }
  for (int i = 0; i < 10; ++i) rows.lambda[i] = i % 3 == 0 ? 0.0 : 0.2;  // rows 0, 3, 6, 9 on their bound
  rows.lambda[10] = 0.2, rows.lambda[11] = -0.3;
  const VecX before = Eigen::Map<const VecX>(rows.lambda.data(), 12);
  DenseLcpMatrix op(W);
  Eigen::Map<VecX> lambda(rows.lambda.data(), 12);
  op.start(lambda, c);
  SubspaceScratch scratch;
  CHECK(subspace_step(op, rows, lambda, 10, scratch) > 0);
  for (int i : {0, 3, 6, 9, 10, 11}) CHECK(lambda[i] == before[i]);
  for (int i = 0; i < 10; ++i) CHECK(lambda[i] >= 0);
  const auto f = [&](const VecX& l) { return 0.5 * l.dot(W * l) + c.dot(l); };
  CHECK(f(lambda) < f(before));
}

TEST_CASE("PGS with subspace steps reaches the tolerance in fewer sweeps and products, at the solution's motion") {
  // 45 rows on 30 DOFs; both runs meet the same natural-residual tolerance.
  std::mt19937 rng(21);
  const int m = 45;
  const MatX W = redundant_delassus(m, 30, rng, 10);
  VecX solution;
  const VecX c = solvable_c(W, rng, solution);
  const double tolerance = 1e-8 * c.norm();
  RowTable plain = unilateral_rows(m), subspace = unilateral_rows(m);
  DenseLcpMatrix plain_op(W), subspace_op(W);
  const VecX weight = VecX::Ones(m);
  const PgsResult a = solve_pgs(plain_op, c, weight, plain, 200000, tolerance);
  const PgsResult b = solve_pgs(subspace_op, c, weight, subspace, 200000, tolerance, 8);
  MESSAGE("plain PGS: " << a.iterations << " sweeps; with subspace steps: " << b.iterations << " sweeps + "
                        << b.subspace_products << " products with W_FF");
  REQUIRE(a.residual <= tolerance);
  REQUIRE(b.residual <= tolerance);
  CHECK(lcp_residual(W, c, subspace) <= tolerance * (1 + 1e-9));
  CHECK(b.iterations + b.subspace_products < a.iterations);
  // W lambda, the motion the multipliers cause, is the same at every solution of a positive
  // semi-definite LCP. For a near-solution l (l >= 0, w = W l + c) and the exact one l*
  // (w* = s >= 0, l*.s = 0): with d = l - l*,
  //   d^T W d = d^T (w - w*) = l.w - l.s - l*.w <= |l.w| + l*.max(-w, 0)
  // and |W d|^2 <= |W| d^T W d: W l is within sqrt(|W| gap) of W l*.
  const double norm = test::max_eigenvalue(W);
  for (const RowTable* run : {&plain, &subspace}) {
    const Eigen::Map<const VecX> l(run->lambda.data(), m);
    const VecX w = W * l + c;
    const double gap = std::abs(l.dot(w)) + solution.dot((-w).cwiseMax(0.0));
    MESSAGE("|W (l - l*)| = " << (W * (l - solution)).norm() << ", bound " << std::sqrt(norm * gap));
    CHECK((W * (l - solution)).norm() <= std::sqrt(norm * gap) * (1 + 1e-6) + 1e-12 * c.norm());
  }
}

namespace {

// DenseLcpMatrix that also counts the non-zero multipliers each start() multiplies W by.
class CountingLcpMatrix {
 public:
  explicit CountingLcpMatrix(const MatX& W) : m_dense(W) {}
  double diagonal(int i) const { return m_dense.diagonal(i); }
  void start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c) {
    products += (lambda.array() != 0).count();
    m_dense.start(lambda, c);
  }
  double w(int i) const { return m_dense.w(i); }
  void changed(int i, double delta) { m_dense.changed(i, delta); }
  void multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> out) const {
    m_dense.multiply_rows(rows, x, out);
  }
  long products = 0;  // columns of W taken by start()

 private:
  DenseLcpMatrix m_dense;
};

// Contacts with two friction rows each (mu 0.4), warm-started at lambda0.
RowTable contact_rows(int contacts, const VecX& lambda0) {
  RowTable rows;
  for (int k = 0; k < contacts; ++k) {
    const int n = rows.add_row(RowKind::Contact, 0, 0, 1e300, 3 * k);
    for (int t = 0; t < 2; ++t) {
      const int r = rows.add_row(RowKind::Friction, 0, 0, 0, 3 * k + 1 + t);
      rows.normal_row[r] = n;
      rows.mu[r] = 0.4;
    }
  }
  for (int i = 0; i < rows.size(); ++i) rows.lambda[i] = lambda0[i];
  return rows;
}

}  // namespace

TEST_CASE("PGS with an offset solves the LCP of c - W offset, with no product at a start from the offset") {
  // The first QP after the Newton predictor: w = C/h at the warm start lambda_0, the LCP's c
  // is C/h - W lambda_0. Given C/h and lambda_0 as the offset, PGS reaches the same
  // tolerance on that LCP, and its first start multiplies W by nothing.
  std::mt19937 rng(5);
  const int contacts = 8, m = 3 * contacts;
  const MatX W = random_spd(m, rng);
  std::uniform_real_distribution<double> uniform(-1, 1);
  VecX lambda0(m), w0(m);
  for (int k = 0; k < contacts; ++k) {
    lambda0[3 * k] = 1 + uniform(rng);  // a push, its friction inside the box
    for (int t = 1; t <= 2; ++t) lambda0[3 * k + t] = 0.2 * lambda0[3 * k] * uniform(rng);
  }
  for (int i = 0; i < m; ++i) w0[i] = 0.5 * uniform(rng);  // C/h: the rows moved since lambda_0
  const VecX c = w0 - W * lambda0;
  // Far above the round-off of w below (~1e-12 here), so that meeting it means something.
  const double tolerance = 1e-6;
  const VecX ones = VecX::Ones(m);
  RowTable plain = contact_rows(contacts, lambda0), shifted = contact_rows(contacts, lambda0);
  CountingLcpMatrix plain_op(W), shifted_op(W);
  const PgsResult a = solve_pgs(plain_op, c, ones, plain, 100000, tolerance, 8);
  // Only the first start is counted: the offset form's later ones (refreshes, after
  // subspace steps) multiply by lambda - lambda_0, which no longer vanishes.
  CountingLcpMatrix first(W);
  RowTable once = contact_rows(contacts, lambda0);
  solve_pgs(first, w0, ones, once, 1, tolerance, 0, lambda0.data());
  CHECK(first.products == 0);
  const PgsResult b = solve_pgs(shifted_op, w0, ones, shifted, 100000, tolerance, 8, lambda0.data());
  MESSAGE("sweeps: " << a.iterations << " plain, " << b.iterations << " with the offset");
  CHECK(a.residual <= tolerance);
  CHECK(b.residual <= tolerance);
  // Both stop on w carried by updates (refreshed every 16 sweeps: an entry of w carries the
  // round-off of at most 16 m column updates and a fresh product's m terms, each about eps
  // |W| |lambda| with lambda, lambda_0 and their difference taken at their largest); a row's
  // natural residual moves by at most as much as its w. Measured afresh on the plain LCP,
  // the offset form's lambda meets the tolerance within that.
  const VecX lambda_b = Eigen::Map<const VecX>(shifted.lambda.data(), m);
  const double eps = std::numeric_limits<double>::epsilon();
  const double largest = 2 * std::max(lambda_b.cwiseAbs().maxCoeff(), lambda0.cwiseAbs().maxCoeff());
  const double roundoff = 17.0 * m * eps * (m * W.cwiseAbs().maxCoeff() * largest + c.cwiseAbs().maxCoeff());
  MESSAGE("round-off allowance " << roundoff << " against the tolerance " << tolerance);
  CHECK(roundoff < 0.01 * tolerance);
  CHECK(lcp_residual(W, c, shifted) <= tolerance + roundoff);
}
