// LinearSolver's multi-column CHOLMOD solve (simplicial: blocks of columns on several
// threads; supernodal: one call): the same solution as one column at a time, to round-off,
// and the same bits on 1 and 2 threads. The supernodal case is what caught Debian's serial
// OpenBLAS returning wrong solutions when two threads called it at once (it fails, not
// always, if the supernodal path is made parallel).
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cstring>
#include <random>

#include "engine/solve/linear_solver.hpp"

using namespace sinew;

namespace {

// A 3D grid Laplacian plus the identity, nx^3 unknowns: SPD with condition number below
// 1 + 12 = 13, so solutions are good to a few ulps times that.
SparseMatrix grid_matrix(int nx) {
  const int n = nx * nx * nx;
  const auto index = [nx](int i, int j, int k) { return (k * nx + j) * nx + i; };
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < nx; ++k)
    for (int j = 0; j < nx; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = index(i, j, k);
        entries.emplace_back(a, a, 7.0);
        if (i + 1 < nx) entries.emplace_back(a, index(i + 1, j, k), -1.0), entries.emplace_back(index(i + 1, j, k), a, -1.0);
        if (j + 1 < nx) entries.emplace_back(a, index(i, j + 1, k), -1.0), entries.emplace_back(index(i, j + 1, k), a, -1.0);
        if (k + 1 < nx) entries.emplace_back(a, index(i, j, k + 1), -1.0), entries.emplace_back(index(i, j, k + 1), a, -1.0);
      }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

MatX random_columns(int rows, int cols) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  MatX B(rows, cols);
  for (int c = 0; c < cols; ++c)
    for (int r = 0; r < rows; ++r) B(r, c) = u(rng);
  return B;
}

MatX solve_with_threads(const SparseMatrix& A, const MatX& B, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  LinearSolver solver(SolverDesc{});
  REQUIRE(solver.factorize(A));
  MatX X;
  solver.solve_many(B, X);
  return X;
}

}  // namespace

TEST_CASE("linear_solver: solve_many equals column-by-column solves, simplicial and supernodal") {
  // 6^3 = 216 unknowns take the simplicial LDL^T path, 11^3 = 1331 the supernodal one.
  for (const int nx : {6, 11}) {
    CAPTURE(nx);
    const SparseMatrix A = grid_matrix(nx);
    CHECK((A.rows() < LinearSolver::kSupernodalThreshold) == (nx == 6));
    // 37 columns: two full blocks and a narrower last one.
    const MatX B = random_columns(static_cast<int>(A.rows()), 2 * LinearSolver::kSolveBlock + 5);
    LinearSolver solver(SolverDesc{});
    REQUIRE(solver.factorize(A));
    MatX X;
    solver.solve_many(B, X);
    REQUIRE(X.rows() == B.rows());
    REQUIRE(X.cols() == B.cols());
    CHECK((A * X - B).norm() / B.norm() < 1e-12);
    for (int c = 0; c < B.cols(); ++c) {
      VecX x;
      solver.solve(B.col(c), x);
      CHECK((X.col(c) - x).norm() <= 1e-12 * x.norm());
    }
    CHECK(solver.solves() == 2 * B.cols());
  }
}

TEST_CASE("linear_solver: solve_many is bit-identical on 1 and 2 threads") {
  const SparseMatrix A = grid_matrix(9);  // 729 unknowns: simplicial, solved in parallel blocks
  const MatX B = random_columns(static_cast<int>(A.rows()), 3 * LinearSolver::kSolveBlock + 1);
  const MatX one = solve_with_threads(A, B, 1);
  const MatX two = solve_with_threads(A, B, 2);
  CHECK(std::memcmp(one.data(), two.data(), sizeof(double) * one.size()) == 0);
}

TEST_CASE("linear_solver: solve_many of no columns is an empty result") {
  LinearSolver solver(SolverDesc{});
  REQUIRE(solver.factorize(grid_matrix(4)));
  MatX X = MatX::Ones(3, 3);
  solver.solve_many(MatX(64, 0), X);
  CHECK(X.rows() == 64);
  CHECK(X.cols() == 0);
}
