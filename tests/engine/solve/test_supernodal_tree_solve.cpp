// SupernodalTreeSolve (engine/solve/supernodal_tree_solve.hpp): one right-hand side split
// over the elimination tree on two threads gives CHOLMOD's solution to round-off, the same
// bits on 1 and 2 threads, covers every supernode once, and declines a tree with no split.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <cstring>
#include <optional>
#include <random>

#include "engine/core/cpu_features.hpp"
#include "engine/solve/linear_solver.hpp"
#include "engine/solve/supernodal_tree_solve.hpp"

using namespace sinew;

namespace {

// Eigen's CHOLMOD wrapper with its factor exposed, in supernodal LL^T with a chosen ordering.
struct Factor : Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> {
  explicit Factor(const SparseMatrix& A, int ordering) {
    setMode(Eigen::CholmodSupernodalLLt);
    cholmod().nmethods = 1;
    cholmod().method[0].ordering = ordering;
    compute(A);
    REQUIRE(info() == Eigen::Success);
    REQUIRE(m_cholmodFactor->is_super);
  }
  const cholmod_factor& L() const { return *m_cholmodFactor; }
};

// The 27-point grid of nx x ny x nz nodes with 3 unknowns each (hex-mesh stiffness's
// pattern), diagonally dominant: SPD with a condition number of a few tens.
SparseMatrix hex_grid_matrix(int nx, int ny, int nz) {
  const auto node = [nx, ny](int i, int j, int k) { return (k * ny + j) * nx + i; };
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = node(i, j, k);
        for (int d = 0; d < 3; ++d) entries.emplace_back(3 * a + d, 3 * a + d, 60.0);
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int p = i + di, q = j + dj, r = k + dk;
              if (p < 0 || q < 0 || r < 0 || p >= nx || q >= ny || r >= nz || node(p, q, r) <= a) continue;
              const int b = node(p, q, r);
              for (int d = 0; d < 3; ++d)
                for (int e = 0; e < 3; ++e) {
                  const double v = d == e ? -1.0 : 0.1;
                  entries.emplace_back(3 * a + d, 3 * b + e, v), entries.emplace_back(3 * b + e, 3 * a + d, v);
                }
            }
      }
  const int n = 3 * nx * ny * nz;
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

SparseMatrix hex_grid_matrix(int nx) { return hex_grid_matrix(nx, nx, nx); }

VecX random_vector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX b(n);
  for (int i = 0; i < n; ++i) b[i] = u(rng);
  return b;
}

long supernode_entries(const cholmod_factor& L) {
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  long sum = 0;
  for (size_t s = 0; s < L.nsuper; ++s) sum += static_cast<long>(super[s + 1] - super[s]) * (pi[s + 1] - pi[s]);
  return sum;
}

}  // namespace

TEST_CASE("supernodal tree solve: CHOLMOD's solution, every supernode once, a split worth two threads") {
  for (const int nx : {8, 11}) {
    CAPTURE(nx);
    const SparseMatrix A = hex_grid_matrix(nx);
    const Factor factor(A, CHOLMOD_NESDIS);
    SupernodalTreeSolve tree;
    tree.analyse(factor.L());
    REQUIRE(tree.usable());
    const long total = supernode_entries(factor.L());
    CHECK(tree.bin_entries(0) + tree.bin_entries(1) + tree.top_entries() == total);
    // What usable() promises: the longer thread's work is at most 3/4 of the whole.
    CHECK(4 * (tree.top_entries() + std::max(tree.bin_entries(0), tree.bin_entries(1))) <= 3 * total);
    CHECK(tree.bin_entries(0) > 0);
    CHECK(tree.bin_entries(1) > 0);
    for (const unsigned seed : {1u, 2u, 3u}) {
      const VecX b = random_vector(static_cast<int>(A.rows()), seed);
      const VecX reference = factor.solve(b);  // cholmod_solve
      VecX x(b.size());
      tree.solve(factor.L(), b.data(), x.data());
      // kappa(A) is a few tens: both within a few hundred ulps of the exact solution.
      CHECK((x - reference).norm() <= 1e-12 * reference.norm());
      // A backward-stable solve leaves a residual of a few hundred eps |A| |x|; |A|_2 <= 92
      // (Gershgorin: 60 on the diagonal, 26 neighbours of row sum 1.2); 1e-13 is 450 eps.
      CHECK((A * x - b).norm() <= 1e-13 * 92 * x.norm());
    }
  }
}

TEST_CASE("supernodal tree solve: bit-identical on 1 and 2 threads") {
  // Its root separator (10 x 10 nodes) is wide enough for both threads to share it
  // (wide_supernode_passes.hpp).
  const SparseMatrix A = hex_grid_matrix(10);
  const Factor factor(A, CHOLMOD_NESDIS);
  const VecX b = random_vector(static_cast<int>(A.rows()), 5);
  const auto solve_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    SupernodalTreeSolve tree;
    tree.analyse(factor.L());
    REQUIRE(tree.usable());
    REQUIRE(WideSupernodePasses::worth_two_threads(tree.widest_top_columns()));
    VecX x(b.size()), single(b.size());
    tree.solve(factor.L(), b.data(), x.data());
    tree.solve(factor.L(), b.data(), x.data());  // again on the same buffers
    const double* values = static_cast<const double*>(factor.L().x);
    const std::vector<float> rounded(values, values + factor.L().xsize);
    tree.solve(factor.L(), rounded.data(), b.data(), single.data());  // single-precision values
    return std::pair{x, single};
  };
  const auto [one, one_single] = solve_with(1);
  const auto [two, two_single] = solve_with(2);
  CHECK(std::memcmp(one.data(), two.data(), sizeof(double) * one.size()) == 0);
  CHECK(std::memcmp(one_single.data(), two_single.data(), sizeof(double) * one.size()) == 0);
}

TEST_CASE("supernodal tree solve: the AVX2 and baseline kernels give the same bits") {
  // tree_kernels.hpp: one order of operations on both builds (supernodes of many widths and
  // heights, dot products with and without a remainder after the groups of four).
  const SparseMatrix A = hex_grid_matrix(10);
  const Factor factor(A, CHOLMOD_NESDIS);
  const VecX b = random_vector(static_cast<int>(A.rows()), 6);
  if (!use_avx2()) MESSAGE("this CPU has no AVX2: both solves take the baseline kernels");
  const auto solve_with = [&](bool baseline) {
    std::optional<BaselineKernelsOnly> scalar_only;
    if (baseline) scalar_only.emplace();
    SupernodalTreeSolve tree;
    tree.analyse(factor.L());
    REQUIRE(tree.usable());
    REQUIRE(WideSupernodePasses::worth_two_threads(tree.widest_top_columns()));  // its root too
    VecX x(b.size());
    tree.solve(factor.L(), b.data(), x.data());
    return x;
  };
  const VecX vector = solve_with(false), scalar = solve_with(true);
  CHECK(std::memcmp(vector.data(), scalar.data(), sizeof(double) * vector.size()) == 0);
}

TEST_CASE("supernodal tree solve: a path-shaped tree has no split") {
  // A tridiagonal matrix in its natural order: each supernode's parent is the next one,
  // and nothing can run beside anything else.
  const int n = 3000;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 4.0);
    if (i + 1 < n) entries.emplace_back(i, i + 1, -1.0), entries.emplace_back(i + 1, i, -1.0);
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  const Factor factor(A, CHOLMOD_NATURAL);
  SupernodalTreeSolve tree;
  tree.analyse(factor.L());
  CHECK_FALSE(tree.usable());
}

TEST_CASE("linear_solver: single solves on a supernodal factor match a simplicial Cholesky") {
  // LinearSolver::solve and a one-column solve_many take the tree solve when the factor's
  // tree splits (its own ordering choice, AMD or nested dissection).
  const SparseMatrix A = hex_grid_matrix(9);
  LinearSolver solver(SolverDesc{});
  REQUIRE(solver.factorize(A));
  const Eigen::SimplicialLLT<SparseMatrix> reference(A);
  const VecX b = random_vector(static_cast<int>(A.rows()), 8);
  const VecX expected = reference.solve(b);
  VecX x;
  solver.solve(b, x);
  CHECK((x - expected).norm() <= 1e-12 * expected.norm());
  MatX X;
  solver.solve_many(MatX(b), X);
  CHECK((X.col(0) - expected).norm() <= 1e-12 * expected.norm());
  // Refactorised with other values (the same pattern): the split is kept, the values new.
  const SparseMatrix doubled = 2.0 * A;
  REQUIRE(solver.factorize(doubled));
  solver.solve(b, x);
  CHECK((x - 0.5 * expected).norm() <= 1e-12 * expected.norm());
}

TEST_CASE("linear_solver: a new analysis does not depend on the solver's history") {
  // A supernodal system (AMD or nested dissection) and then, after reset_pattern, a
  // simplicial one (CHOLMOD's default ordering), as when bodies fall asleep: the same factor
  // and the same bits as a fresh solver's. On this 270-DOF grid nested dissection would fill
  // less than CHOLMOD's default (12,321 entries against 12,510), so a setting left over from
  // the larger system would show (it did, with the reset taken out).
  const SparseMatrix large = hex_grid_matrix(11), small = hex_grid_matrix(6, 5, 3);
  REQUIRE(small.rows() < LinearSolver::kSupernodalThreshold);
  LinearSolver used(SolverDesc{});
  REQUIRE(used.factorize(large));
  used.reset_pattern();
  REQUIRE(used.factorize(small));
  LinearSolver fresh(SolverDesc{});
  REQUIRE(fresh.factorize(small));
  CHECK(used.factor_entries() == fresh.factor_entries());
  const VecX b = random_vector(static_cast<int>(small.rows()), 9);
  VecX x_used, x_fresh;
  used.solve(b, x_used);
  fresh.solve(b, x_fresh);
  CHECK(std::memcmp(x_used.data(), x_fresh.data(), sizeof(double) * b.size()) == 0);
}

namespace {

// A copy of L whose values are L's rounded to single precision (and back): the factor that
// a solve reading single-precision values solves with.
struct RoundedFactor {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  explicit RoundedFactor(const cholmod_factor& from) {
    cholmod_start(&common);
    L = cholmod_copy_factor(const_cast<cholmod_factor*>(&from), &common);
    REQUIRE(L);
    double* x = static_cast<double*>(L->x);
    for (size_t k = 0; k < L->xsize; ++k) x[k] = static_cast<double>(static_cast<float>(x[k]));
  }
  ~RoundedFactor() {
    cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }
};

std::vector<float> single_values(const cholmod_factor& L) {
  const double* x = static_cast<const double*>(L.x);
  return std::vector<float>(x, x + L.xsize);
}

}  // namespace

TEST_CASE("supernodal tree solve: single-precision values solve exactly with the rounded factor") {
  // Split (a 10^3 grid, nested dissection) and in order on one thread (a 3 x 3 x 4 grid in
  // natural order, whose tree has no split worth it): the values widen to double exactly,
  // so the solve is the double solve with the rounded factor, bit for bit.
  for (const auto& [A, ordering, split] : {std::tuple{hex_grid_matrix(10), CHOLMOD_NESDIS, true},
                                           std::tuple{hex_grid_matrix(3, 3, 4), CHOLMOD_NATURAL, false}}) {
    CAPTURE(split);
    const Factor factor(A, ordering);
    const RoundedFactor rounded(factor.L());
    SupernodalTreeSolve tree, rounded_tree;
    tree.analyse(factor.L());
    rounded_tree.analyse(*rounded.L);
    REQUIRE(tree.ordered());
    REQUIRE(tree.usable() == split);
    const std::vector<float> values = single_values(factor.L());
    const VecX b = random_vector(static_cast<int>(A.rows()), 9);
    VecX single(b.size()), expected(b.size()), exact(b.size());
    tree.solve(factor.L(), values.data(), b.data(), single.data());
    rounded_tree.solve(*rounded.L, b.data(), expected.data());
    CHECK(std::memcmp(single.data(), expected.data(), sizeof(double) * single.size()) == 0);
    // Against A^-1 b: L~ = L + E, |E| <= u |L| entrywise (u = 2^-24), so A~ - A is about
    // 2u |L| |L|^T, and the solution moves by kappa(A) of that relative to A. kappa <= 3.2
    // (Gershgorin: eigenvalues in [60 - 31.2, 60 + 31.2]); 1e-6 is 5 kappa u per factor of L.
    tree.solve(factor.L(), b.data(), exact.data());
    const double error = (single - exact).norm() / exact.norm();
    MESSAGE("single against double: relative " << error);
    CHECK(error <= 1e-6);
    CHECK(error > 0);  // the rounded values were read, not the factor's own
  }
}

TEST_CASE("supernodal tree solve: single-precision values give the same bits on AVX2 and baseline kernels") {
  // Split, and in order on one thread (the grids of the test above).
  if (!use_avx2()) MESSAGE("this CPU has no AVX2: both solves take the baseline kernels");
  for (const auto& [A, ordering] : {std::pair{hex_grid_matrix(10), CHOLMOD_NESDIS},
                                    std::pair{hex_grid_matrix(3, 3, 4), CHOLMOD_NATURAL}}) {
    const Factor factor(A, ordering);
    const std::vector<float> values = single_values(factor.L());
    const VecX b = random_vector(static_cast<int>(A.rows()), 10);
    const auto solve_with = [&](bool baseline) {
      std::optional<BaselineKernelsOnly> scalar_only;
      if (baseline) scalar_only.emplace();
      SupernodalTreeSolve tree;
      tree.analyse(factor.L());
      VecX x(b.size());
      tree.solve(factor.L(), values.data(), b.data(), x.data());
      return x;
    };
    const VecX vector = solve_with(false), scalar = solve_with(true);
    CHECK(std::memcmp(vector.data(), scalar.data(), sizeof(double) * vector.size()) == 0);
  }
}

TEST_CASE("linear_solver: preconditioner solves read single-precision values of the current factorisation") {
  // solver.stale_factor_precision: "single" reads a float copy made after each
  // factorisation, only for FactorUse::Preconditioner; "double" and exact solves read the factor.
  const SparseMatrix A = hex_grid_matrix(9);
  const VecX b = random_vector(static_cast<int>(A.rows()), 11);
  SolverDesc single_desc, double_desc;
  single_desc.stale_factor_precision = "single";
  double_desc.stale_factor_precision = "double";
  LinearSolver single(single_desc), twice(double_desc);
  REQUIRE(single.factorize(A));
  REQUIRE(twice.factorize(A));
  VecX exact, preconditioner, double_preconditioner;
  single.solve(b, exact);
  single.solve(b, preconditioner, LinearSolver::FactorUse::Preconditioner);
  twice.solve(b, double_preconditioner, LinearSolver::FactorUse::Preconditioner);
  CHECK(std::memcmp(exact.data(), double_preconditioner.data(), sizeof(double) * exact.size()) == 0);
  const double error = (preconditioner - exact).norm() / exact.norm();
  CHECK(error > 0);
  CHECK(error <= 1e-6);  // as in the tree solve's test above (the same kind of matrix, the same kappa bound)
  // Refactorised with other values: the copy follows (a stale copy would return 2x the answer).
  REQUIRE(single.factorize(2.0 * A));
  single.solve(b, preconditioner, LinearSolver::FactorUse::Preconditioner);
  CHECK((preconditioner - 0.5 * exact).norm() <= 1e-6 * 0.5 * exact.norm());
}

TEST_CASE("linear_solver: CG preconditioned with single-precision values of an ill-conditioned factor") {
  // A = eps I + K, K the 27-point lattice Laplacian (3 unknowns a node; its null space the
  // constants): kappa(A) ~ 52 / eps = 5e4, as a step matrix M / h^2 + K of a stiff body.
  // The float copy's factor solves A~ = L~ L~^T with |A~ - A| <~ 2u |L| |L|^T (u = 2^-24), so
  // rho = |I - A~^-1 A| <~ 2u kappa = 6e-3 for |L| |L|^T ~ |A|; CG then gains at least a
  // factor 1/rho an iteration: 1e-12 in 6, or in 12 if |L| |L|^T is 10x |A|.
  const int nx = 10, n = 3 * nx * nx * nx;
  const auto node = [nx](int i, int j, int k) { return (k * nx + j) * nx + i; };
  const double eps = 1e-3;
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < nx; ++k)
    for (int j = 0; j < nx; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = node(i, j, k);
        int degree = 0;
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int p = i + di, q = j + dj, r = k + dk;
              if ((di | dj | dk) == 0 || p < 0 || q < 0 || r < 0 || p >= nx || q >= nx || r >= nx) continue;
              ++degree;
              for (int d = 0; d < 3; ++d) entries.emplace_back(3 * a + d, 3 * node(p, q, r) + d, -1.0);
            }
        for (int d = 0; d < 3; ++d) entries.emplace_back(3 * a + d, 3 * a + d, degree + eps);
      }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  // As a step matrix: full node blocks (the pattern multiply_node_blocked reads).
  for (int a = 0; a < n / 3; ++a)
    for (int b = 0; b < n / 3; ++b)
      if (A.coeff(3 * a, 3 * b) != 0)
        for (int d = 0; d < 3; ++d)
          for (int e = 0; e < 3; ++e)
            if (d != e) A.coeffRef(3 * a + d, 3 * b + e) = 0.0;
  A.makeCompressed();
  LinearSolver solver(SolverDesc{});  // stale_factor_precision "single"
  REQUIRE(solver.factorize(A));
  const VecX b = random_vector(n, 12);
  VecX x;
  const int iterations = solver.solve_preconditioned(A, b, x, 1e-12, 50, 0);
  MESSAGE("CG iterations to 1e-12 with the single-precision preconditioner: " << iterations);
  // The rounded factor is not A's: one iteration leaves a residual of about rho |b| (~6e-3
  // |b|, far above 1e-12), so at least two.
  CHECK(iterations >= 2);
  CHECK(iterations <= 12);
  CHECK((b - A * x).norm() <= 1e-12 * b.norm());
}
