// LinearSolver::holds_factor_of: true exactly when the last factorisation succeeded, was
// made with keep_factored_matrix on, and was of the very matrix asked about (pattern and
// values bit for bit), so that keeping its factor is the same as factorising again.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "engine/solve/linear_solver.hpp"
#include "tests/support/grid_matrices.hpp"

using namespace sinew;

TEST_CASE("linear_solver: holds_factor_of the matrix it last factorised, bit for bit") {
  const SparseMatrix A = test::grid_laplacian(7);  // 343 unknowns: supernodal Cholesky, which fails on an indefinite matrix
  REQUIRE(A.isCompressed());
  LinearSolver solver(SolverDesc{});

  SUBCASE("not without keep_factored_matrix") {
    REQUIRE(solver.factorize(A));
    CHECK_FALSE(solver.holds_factor_of(A));
  }
  SUBCASE("a copy of the matrix factorised, and its factor solves as a new one of it") {
    solver.keep_factored_matrix(true);
    CHECK_FALSE(solver.holds_factor_of(A));  // nothing factorised yet
    REQUIRE(solver.factorize(A));
    const SparseMatrix copy = A;  // another matrix object with the same pattern and values
    CHECK(solver.holds_factor_of(copy));
    LinearSolver fresh(SolverDesc{});
    REQUIRE(fresh.factorize(copy));
    VecX b = VecX::LinSpaced(A.rows(), -1, 2), x, y;
    solver.solve(b, x);
    fresh.solve(b, y);
    CHECK(x == y);
  }
  SUBCASE("not after one value moved by one ulp, nor a signed zero flipped") {
    solver.keep_factored_matrix(true);
    REQUIRE(solver.factorize(A));
    SparseMatrix moved = A;
    moved.valuePtr()[moved.nonZeros() / 2] =
        std::nextafter(moved.valuePtr()[moved.nonZeros() / 2], std::numeric_limits<double>::infinity());
    CHECK_FALSE(solver.holds_factor_of(moved));
    SparseMatrix with_zero = A;
    with_zero.coeffRef(0, 1) = 0.0;  // stored entry
    REQUIRE(solver.factorize(with_zero));
    CHECK(solver.holds_factor_of(with_zero));
    with_zero.coeffRef(0, 1) = -0.0;
    CHECK_FALSE(solver.holds_factor_of(with_zero));
  }
  SUBCASE("not for another pattern, nor after reset_pattern") {
    solver.keep_factored_matrix(true);
    REQUIRE(solver.factorize(A));
    SparseMatrix other = A;
    other.coeffRef(0, A.cols() - 1) = 0;  // a new stored entry: same values, another pattern
    other.coeffRef(A.cols() - 1, 0) = 0;
    other.makeCompressed();
    REQUIRE(other.nonZeros() == A.nonZeros() + 2);
    CHECK_FALSE(solver.holds_factor_of(other));
    solver.reset_pattern();
    CHECK_FALSE(solver.holds_factor_of(A));
  }
  SUBCASE("not after a factorisation that failed, of that matrix or the one before") {
    solver.keep_factored_matrix(true);
    REQUIRE(solver.factorize(A));
    SparseMatrix indefinite = A;
    indefinite.coeffRef(3, 3) = -1e3;
    CHECK_FALSE(solver.factorize(indefinite));
    CHECK_FALSE(solver.holds_factor_of(indefinite));
    CHECK_FALSE(solver.holds_factor_of(A));
  }
}
