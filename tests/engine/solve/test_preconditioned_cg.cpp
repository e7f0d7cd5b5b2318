// LinearSolver::solve_preconditioned: conjugate gradients on a matrix other than the one
// factorised, preconditioned with that factorisation (the Newton directions between
// factorisations, solve_newton.cpp). Convergence at the rate the preconditioned spectrum
// allows, the stopping rule with and without a scale, and its refusals.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "engine/solve/linear_solver.hpp"
#include "tests/support/grid_matrices.hpp"

using namespace sinew;

namespace {

VecX random_vector(Eigen::Index n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX b(n);
  for (Eigen::Index i = 0; i < n; ++i) b[i] = u(rng);
  return b;
}

// A = 7 I - adjacency of an 11^3 grid, three unknowns a point in the node blocks of a step
// matrix (3,993 unknowns, a supernodal factor): eigenvalues in [1, 13]. The factorised "older" matrix is A + 0.5 I, so the preconditioned operator
// (A + 0.5 I)^-1 A has eigenvalues 1 - 0.5 / mu, mu in [1.5, 13.5]: within [0.667, 0.963],
// condition number kappa <= 1.45.
struct Shifted {
  SparseMatrix A = test::node_blocked_grid_laplacian(11);
  LinearSolver solver{SolverDesc{}};
  Shifted() {
    SparseMatrix older = A;
    for (int i = 0; i < older.rows(); ++i) older.coeffRef(i, i) += 0.5;
    REQUIRE(solver.factorize(older));
  }
};

}  // namespace

TEST_CASE("preconditioned CG: converges to the tolerance at the preconditioned spectrum's rate") {
  Shifted s;
  const VecX b = random_vector(s.A.rows());
  VecX x;
  const double tolerance = 1e-10;
  const int iterations = s.solver.solve_preconditioned(s.A, b, x, tolerance, 50);
  // CG: |e_k|_A <= 2 rho^k |e_0|_A, rho = (sqrt(kappa) - 1) / (sqrt(kappa) + 1) <= 0.093;
  // residuals carry a further sqrt(cond(A)) <= sqrt(13): 2 sqrt(13) 0.093^k <= 1e-10 by k = 11.
  CHECK(iterations > 0);
  CHECK(iterations <= 11);
  CHECK((b - s.A * x).norm() <= tolerance * b.norm());
  // The error from the residual: |x - A^-1 b| <= |r| / lambda_min(A), lambda_min >= 1.
  LinearSolver exact{SolverDesc{}};
  REQUIRE(exact.factorize(s.A));
  VecX reference = VecX::Zero(b.size());
  exact.solve(b, reference);
  CHECK((x - reference).norm() <= tolerance * b.norm() * (1 + 1e-6));
}

TEST_CASE("preconditioned CG: a scale above |b| stops at tolerance times that scale") {
  Shifted s;
  const VecX b = random_vector(s.A.rows());
  VecX plain, scaled, below;
  const double tolerance = 1e-10, scale = 1e4 * b.norm();
  const int plain_iterations = s.solver.solve_preconditioned(s.A, b, plain, tolerance, 50);
  const int scaled_iterations = s.solver.solve_preconditioned(s.A, b, scaled, tolerance, 50, scale);
  CHECK(scaled_iterations > 0);
  CHECK(scaled_iterations < plain_iterations);
  CHECK((b - s.A * scaled).norm() <= tolerance * scale);
  // A scale below |b| changes nothing: the rule is tolerance max(|b|, scale).
  CHECK(s.solver.solve_preconditioned(s.A, b, below, tolerance, 50, 0.5 * b.norm()) == plain_iterations);
  CHECK(below == plain);
  // |b| already below the target: no iteration, x = 0.
  VecX none;
  CHECK(s.solver.solve_preconditioned(s.A, b, none, tolerance, 50, 2 * b.norm() / tolerance) == 0);
  CHECK(none.isZero(0));
}

TEST_CASE("preconditioned CG: refuses when the cap is too low or A shows no positive curvature") {
  Shifted s;
  const VecX b = random_vector(s.A.rows());
  VecX x;
  CHECK(s.solver.solve_preconditioned(s.A, b, x, 1e-10, 2) == -1);
  SparseMatrix negative = -s.A;  // negative definite: p^T A p < 0 on the first direction
  CHECK(s.solver.solve_preconditioned(negative, b, x, 1e-10, 50) == -1);
}
