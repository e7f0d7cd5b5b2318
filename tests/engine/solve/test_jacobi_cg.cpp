// JacobiCg (solver.linear "pcg"): convergence to its tolerance on an SPD grid system, the
// warm start, the iteration cap, b = 0, and the same bits on 1 and 2 threads.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <random>

#include "engine/solve/jacobi_cg.hpp"
#include "engine/solve/linear_solver.hpp"
#include "tests/support/grid_matrices.hpp"

using namespace sinew;

namespace {

VecX random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX b(n);
  for (Eigen::Index i = 0; i < n; ++i) b[i] = u(rng);
  return b;
}

}  // namespace

TEST_CASE("Jacobi CG: converges to its tolerance, and the error is what the residual allows") {
  // 7 I - adjacency of a 30^3 grid (27,000 unknowns, ~186k entries: multiply_system runs in
  // parallel): eigenvalues in [1, 13], so |x - A^-1 b| <= |b - A x| / 1.
  const SparseMatrix A = test::grid_laplacian(30);
  const VecX b = random_vector(A.rows(), 3);
  JacobiCg cg;
  cg.compute(A);
  VecX x;
  const double tolerance = 1e-10;
  const JacobiCg::Result result = cg.solve(A, b, x, tolerance, 1000);
  CHECK(result.converged);
  // CG on a condition number <= 13: |e_k|_A <= 2 rho^k |e_0|_A, rho = (sqrt(13) - 1) / (sqrt(13) + 1)
  // = 0.566; with sqrt(13) more for residuals, 1e-10 by k = 45.
  CHECK(result.iterations > 0);
  CHECK(result.iterations <= 45);
  CHECK((b - A * x).norm() < tolerance * b.norm());
  CHECK(result.error < tolerance);
  LinearSolver exact{SolverDesc{}};
  REQUIRE(exact.factorize(A));
  VecX reference = VecX::Zero(b.size());
  exact.solve(b, reference);
  CHECK((x - reference).norm() <= tolerance * b.norm() * (1 + 1e-6));
  // From the solution it was given, nothing to do.
  VecX again = x;
  const JacobiCg::Result warm = cg.solve(A, b, again, tolerance, 1000);
  CHECK(warm.iterations == 0);
  CHECK(warm.converged);
  CHECK(again == x);
}

TEST_CASE("Jacobi CG: the cap stops it unconverged; b = 0 gives x = 0") {
  const SparseMatrix A = test::grid_laplacian(10);
  const VecX b = random_vector(A.rows(), 5);
  JacobiCg cg;
  cg.compute(A);
  VecX x;
  const JacobiCg::Result capped = cg.solve(A, b, x, 1e-12, 3);
  CHECK(capped.iterations == 3);
  CHECK_FALSE(capped.converged);
  CHECK(capped.error == doctest::Approx((b - A * x).norm() / b.norm()).epsilon(1e-12));
  // CG's bound on the A-norm error, |e_k|_A <= 2 rho^k |e_0|_A (rho = 0.566, the spectrum in
  // [1, 13]), in the quadratic phi(x) = 1/2 x^T A x - b^T x, whose minimum is phi* = -1/2 b^T x*:
  // phi(x_3) - phi* <= 4 rho^6 (0 - phi*), so phi(x_3) <= (1 - 4 rho^6) phi* = 0.868 phi*.
  LinearSolver exact{SolverDesc{}};
  REQUIRE(exact.factorize(A));
  VecX solution = VecX::Zero(b.size());
  exact.solve(b, solution);
  const double phi_star = -0.5 * b.dot(solution), rho = 0.566;
  CHECK(0.5 * x.dot(A * x) - b.dot(x) <= (1 - 4 * std::pow(rho, 6)) * phi_star);
  VecX zero = VecX::Ones(A.rows());
  const JacobiCg::Result none = cg.solve(A, VecX::Zero(A.rows()), zero, 1e-12, 3);
  CHECK(none.iterations == 0);
  CHECK(zero.isZero(0));
}

TEST_CASE("Jacobi CG: the same bits on 1 and 2 threads") {
  const SparseMatrix A = test::grid_laplacian(30);  // above multiply_system's parallel threshold
  const VecX b = random_vector(A.rows(), 9);
  VecX x1, x2;
  JacobiCg cg;
  cg.compute(A);
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    cg.solve(A, b, x1, 1e-10, 1000);
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    cg.solve(A, b, x2, 1e-10, 1000);
  }
  REQUIRE(x1.size() == x2.size());
  CHECK(std::memcmp(x1.data(), x2.data(), sizeof(double) * x1.size()) == 0);
}

TEST_CASE("Jacobi CG: the diagonal undoes a bad scaling; an indefinite A stops it unconverged") {
  // D L D with D spanning six decades: Jacobi's D^-2 / 7 turns the operator into one similar
  // to L / 7, so the A-norm error still falls by rho = 0.566 an iteration; the residual now
  // carries sqrt(cond(A)) <= sqrt(13 (1e6)^2) = 3.6e6: 2 3.6e6 0.566^k <= 1e-10 by k = 69.
  // Any other preconditioner leaves a condition number ~1e13: millions of iterations.
  const SparseMatrix L = test::grid_laplacian(30);
  VecX d(L.rows());
  for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = std::pow(10.0, 6.0 * static_cast<double>(i % 7) / 6.0 - 3.0);
  SparseMatrix A = L;
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) it.valueRef() *= d[it.row()] * d[it.col()];
  const VecX b = random_vector(A.rows(), 13);
  JacobiCg cg;
  cg.compute(A);
  VecX x = VecX::Ones(7);  // a wrong size: restarted from zero
  const JacobiCg::Result result = cg.solve(A, b, x, 1e-10, 1000);
  CHECK(result.converged);
  CHECK(result.iterations <= 69);
  CHECK(x.size() == b.size());
  CHECK((b - A * x).norm() < 1e-10 * b.norm());
  // -L: the first search direction has negative curvature; x stays where it started.
  const SparseMatrix negative = -L;
  cg.compute(negative);
  VecX y = VecX::Zero(L.rows());
  const JacobiCg::Result refused = cg.solve(negative, b, y, 1e-10, 1000);
  CHECK_FALSE(refused.converged);
  CHECK(refused.iterations == 0);
  CHECK(y.isZero(0));
  // A matrix and a preconditioner of different sizes are a programming error.
  CHECK_THROWS_AS(cg.solve(test::grid_laplacian(5), VecX::Ones(125), y, 1e-10, 10), std::logic_error);
}
