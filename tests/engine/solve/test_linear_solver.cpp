// LinearSolver's multi-column CHOLMOD solve (blocks of columns on several threads:
// simplicial factors through cholmod_solve2, supernodal ones through SupernodalBlockSolve):
// the same solution as one column at a time through CHOLMOD, to round-off, and the same bits
// on 1 and 2 threads. The supernodal path once called CHOLMOD from two threads at once and
// Debian's serial OpenBLAS returned wrong solutions; SupernodalBlockSolve calls no BLAS.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cstring>
#include <random>

#include "engine/solve/linear_solver.hpp"
#include "tests/support/grid_matrices.hpp"

using namespace sinew;

namespace {

SparseMatrix grid_matrix(int nx) { return test::grid_laplacian(nx); }

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

// Columns with `nonzeros` random entries each at scattered rows (all rows when nonzeros is
// 0): sparse ones start at different positions of the factor's order, so the supernodal
// path reorders them and skips supernodes.
static MatX sparse_columns(int rows, int cols, int nonzeros) {
  if (nonzeros == 0) return random_columns(rows, cols);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> row(0, rows - 1);
  MatX B = MatX::Zero(rows, cols);
  for (int c = 0; c < cols; ++c)
    for (int k = 0; k < nonzeros; ++k) B(row(rng), c) = u(rng);
  return B;
}

TEST_CASE("linear_solver: solve_many is bit-identical on 1 and 2 threads") {
  // 216 unknowns: simplicial; 1331: supernodal. Column counts that make one block, two
  // narrow ones and several full ones with a narrower last; dense, 12-entry and unit columns.
  for (const int nx : {6, 11})
    for (const int cols : {1, 5, 3 * LinearSolver::kSolveBlock + 1})
      for (const int nonzeros : {0, 12, 1}) {
        CAPTURE(nx);
        CAPTURE(cols);
        CAPTURE(nonzeros);
        const SparseMatrix A = grid_matrix(nx);
        REQUIRE((A.rows() < LinearSolver::kSupernodalThreshold) == (nx == 6));
        const MatX B = sparse_columns(static_cast<int>(A.rows()), cols, nonzeros);
        const MatX one = solve_with_threads(A, B, 1);
        const MatX two = solve_with_threads(A, B, 2);
        CHECK(std::memcmp(one.data(), two.data(), sizeof(double) * one.size()) == 0);
        CHECK((A * one - B).norm() <= 1e-12 * B.norm());
      }
}

TEST_CASE("linear_solver: supernodal solve_many of unit columns (sparse right-hand sides)") {
  // H^-1 on a few nodes (touched_inverse.hpp): unit-vector columns in any order, whose
  // forward pass skips the supernodes off their elimination-tree paths. Each count is solved
  // after a wider one on the same workspaces, so a narrower call must not read a wider one's
  // leftovers.
  const SparseMatrix A = grid_matrix(11);
  const int n = static_cast<int>(A.rows());
  LinearSolver solver(SolverDesc{});
  REQUIRE(solver.factorize(A));
  for (const int cols : {40, 17, 6, 2, 1}) {
    CAPTURE(cols);
    MatX B = MatX::Zero(n, cols);
    for (int c = 0; c < cols; ++c) B((c * 7919 + 13) % n, c) = 1.0;
    MatX X;
    solver.solve_many(B, X);
    for (int c = 0; c < cols; ++c) {
      VecX x;
      solver.solve(B.col(c), x);
      // kappa(A) < 13: both solutions are within a few ulps times 13 of the exact one.
      CHECK((X.col(c) - x).norm() <= 1e-12 * x.norm());
    }
    CHECK((A * X - B).norm() / B.norm() < 1e-12);
  }
}

TEST_CASE("linear_solver: solve_many reading B through its column pattern gives the same bits") {
  // Sparse right-hand sides (a row's stencil), their nonzeros named by a pattern that also
  // lists rows holding zeros and one row twice: B is read there only, and X is bit for bit
  // the solve that scans every row, with and without wanted rows.
  const SparseMatrix A = grid_matrix(11);
  const int n = static_cast<int>(A.rows());
  LinearSolver solver(SolverDesc{});
  REQUIRE(solver.factorize(A));
  REQUIRE(solver.honours_wanted_rows());
  const int cols = 23;
  MatX B = MatX::Zero(n, cols);
  std::vector<int> start{0}, rows, wanted;
  for (int c = 0; c < cols; ++c) {
    for (int k = 0; k < 4; ++k) {
      const int r = (c * 389 + k * 97) % n;
      B(r, c) = 1.0 + k;
      rows.push_back(r);
      wanted.push_back(r);
    }
    rows.push_back((c * 389 + 5) % n);  // a zero entry named anyway
    rows.push_back(rows[start.back()]);  // and a row named twice
    start.push_back(static_cast<int>(rows.size()));
  }
  const LinearSolver::ColumnPattern pattern{start, rows};
  const std::vector<int>* wanted_cases[] = {nullptr, &wanted};
  for (const std::vector<int>* w : wanted_cases) {
    MatX scanned(n, cols), patterned(n, cols);
    solver.solve_many(B, scanned, w);
    solver.solve_many(B, patterned, w, &pattern);
    CHECK(std::memcmp(scanned.data(), patterned.data(), sizeof(double) * n * cols) == 0);
  }
  // B is read through the pattern only: a pattern that leaves out column 0's first nonzero
  // solves as if it were zero.
  std::vector<int> short_rows = rows;
  short_rows[0] = short_rows[start[1] - 1] = short_rows[3];  // r0 and its repeat named r3
  const LinearSolver::ColumnPattern short_pattern{start, short_rows};
  MatX full(n, cols), partial(n, cols);
  solver.solve_many(B, full);
  solver.solve_many(B, partial, nullptr, &short_pattern);
  MatX B_without = B;
  B_without(rows[0], 0) = 0;
  MatX expected(n, cols);
  solver.solve_many(B_without, expected);
  CHECK((partial.col(0) - full.col(0)).norm() > 0.1 * full.col(0).norm());
  CHECK(std::memcmp(partial.data(), expected.data(), sizeof(double) * n * cols) == 0);
}

// The grid matrix with diagonal links in every x-y plane too, and a diagonal large enough to
// keep it dominant: the same size, another sparsity pattern.
static SparseMatrix grid_matrix_with_diagonals(int nx) {
  SparseMatrix A = grid_matrix(nx);
  const auto index = [nx](int i, int j, int k) { return (k * nx + j) * nx + i; };
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < nx; ++k)
    for (int j = 0; j + 1 < nx; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const int a = index(i, j, k), b = index(i + 1, j + 1, k);
        entries.emplace_back(a, b, -0.5), entries.emplace_back(b, a, -0.5);
      }
  for (int a = 0; a < A.rows(); ++a) entries.emplace_back(a, a, 1.0);
  SparseMatrix extra(A.rows(), A.cols());
  extra.setFromTriplets(entries.begin(), entries.end());
  return A + extra;
}

TEST_CASE("linear_solver: supernodal solve_many after a new symbolic analysis") {
  // reset_pattern and another matrix (another size, then the same size with another
  // pattern): the block solve reads the new factor's supernodes.
  LinearSolver solver(SolverDesc{});
  for (int trial = 0; trial < 3; ++trial) {
    CAPTURE(trial);
    const SparseMatrix A = trial == 0 ? grid_matrix(12) : trial == 1 ? grid_matrix(11) : grid_matrix_with_diagonals(11);
    solver.reset_pattern();
    REQUIRE(solver.factorize(A));
    const MatX B = random_columns(static_cast<int>(A.rows()), 9);
    MatX X;
    solver.solve_many(B, X);
    CHECK((A * X - B).norm() / B.norm() < 1e-12);
  }
}

TEST_CASE("linear_solver: solve_many of no columns is an empty result") {
  LinearSolver solver(SolverDesc{});
  REQUIRE(solver.factorize(grid_matrix(4)));
  MatX X = MatX::Ones(3, 3);
  solver.solve_many(MatX(64, 0), X);
  CHECK(X.rows() == 64);
  CHECK(X.cols() == 0);
}
