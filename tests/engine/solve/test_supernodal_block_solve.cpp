// SupernodalBlockSolve (engine/solve/supernodal_block_solve.hpp) on a block-diagonal matrix,
// as several bodies make: a block of columns on one body's unknowns works on that body's
// part of L alone (its backward pass skips the other parts, whose solution is zero), and
// the solution is the same as with every supernode visited.
#include <doctest/doctest.h>

#include <Eigen/CholmodSupport>
#include <cstring>

#include "engine/core/cpu_features.hpp"
#include "engine/solve/supernodal_block_solve.hpp"
#include "engine/solve/supernode_view.hpp"

#include "tests/support/grid_matrices.hpp"

using namespace sinew;

namespace {

// Two disconnected grids, as two bodies make (grid_matrices.hpp).
SparseMatrix two_disconnected_grids(int nx) { return test::grid_laplacian(nx, 2); }

struct BlockTestFactor : Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> {
  explicit BlockTestFactor(const SparseMatrix& A) {
    setMode(Eigen::CholmodSupernodalLLt);
    compute(A);
    REQUIRE(info() == Eigen::Success);
    REQUIRE(m_cholmodFactor->is_super);
  }
  const cholmod_factor& L() const { return *m_cholmodFactor; }
};

// Supernodes whose unknowns are all in the first `n` rows of A (the first grid).
int supernodes_of_first(const cholmod_factor& L, int n) {
  const int* perm = static_cast<const int*>(L.Perm);
  int count = 0;
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s) {
    const SupernodeView view = supernode_view(L, s);
    bool first = true;
    for (int k = view.first; k < view.first + view.columns; ++k) first = first && perm[k] < n;
    count += first;
  }
  return count;
}

// The two grids, their factor and a block solve analysed for it.
struct GridSolve {
  explicit GridSolve(int nx) : n(nx * nx * nx), A(two_disconnected_grids(nx)), factor(A) {
    solve.analyse(factor.L());
    solve.prepare(ws);
  }
  int n;
  SparseMatrix A;
  BlockTestFactor factor;
  SupernodalBlockSolve solve;
  SupernodalBlockSolve::Workspace ws;
};

}  // namespace

TEST_CASE("supernodal block solve: columns on one of two disconnected grids skip the other's supernodes") {
  GridSolve grids(9);
  const int n = grids.n;
  const SparseMatrix& A = grids.A;
  const cholmod_factor& L = grids.factor.L();
  SupernodalBlockSolve& solve = grids.solve;
  SupernodalBlockSolve::Workspace& ws = grids.ws;
  const int first_supernodes = supernodes_of_first(L, n);
  // Each supernode holds unknowns of one grid only (no entry couples them).
  REQUIRE(first_supernodes > 0);
  REQUIRE(first_supernodes < static_cast<int>(L.nsuper));

  SUBCASE("unit columns in the first grid") {
    const int width = 5;
    MatX B = MatX::Zero(2 * n, width), X(2 * n, width);
    for (int c = 0; c < width; ++c) B((c * 131 + 17) % n, c) = 1.0;
    solve.solve(L, B.data(), 2 * n, X.data(), 2 * n, width, ws);
    // kappa(A) < 13: the residual is round-off.
    CHECK((A * X - B).norm() <= 1e-12 * B.norm());
    // The second grid's part of the solution is exactly zero: never computed.
    CHECK(X.bottomRows(n).cwiseAbs().maxCoeff() == 0.0);
    // The backward pass reached the first grid's root, hence every supernode below it, and
    // none of the second grid's.
    CHECK(ws.backward_supernodes == first_supernodes);
    // The skipped parts are exactly what a full backward pass computes: with a sixth column on
    // the second grid in the block (the same kernel width, 8, whose columns do not mix), every
    // supernode is visited, and the first five columns come out bit for bit the same.
    MatX B6 = MatX::Zero(2 * n, width + 1), X6(2 * n, width + 1);
    B6.leftCols(width) = B;
    B6(n + 40, width) = 1.0;
    solve.solve(L, B6.data(), 2 * n, X6.data(), 2 * n, width + 1, ws);
    CHECK(ws.backward_supernodes == static_cast<int>(L.nsuper));
    CHECK((X6.leftCols(width) - X).cwiseAbs().maxCoeff() == 0.0);
    // The same columns one at a time: the same solutions, each on the first grid's part alone.
    for (int c = 0; c < width; ++c) {
      VecX x(2 * n);
      solve.solve(L, B.col(c).data(), 2 * n, x.data(), 2 * n, 1, ws);
      CHECK((x - X.col(c)).norm() <= 1e-14 * x.norm());
      CHECK(ws.backward_supernodes == first_supernodes);
    }
  }

  SUBCASE("a column on both grids visits every supernode") {
    VecX b = VecX::Zero(2 * n), x(2 * n);
    b[3] = 1.0;
    b[n + 5] = -2.0;
    solve.solve(L, b.data(), 2 * n, x.data(), 2 * n, 1, ws);
    CHECK((A * x - b).norm() <= 1e-12 * b.norm());
    CHECK(ws.backward_supernodes == static_cast<int>(L.nsuper));
  }

  SUBCASE("a zero column visits nothing and solves to zero") {
    MatX B = MatX::Zero(2 * n, 2), X = MatX::Constant(2 * n, 2, 1.0);
    solve.solve(L, B.data(), 2 * n, X.data(), 2 * n, 2, ws);
    CHECK(ws.backward_supernodes == 0);
    CHECK(X.cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("supernodal block solve: wanted rows come out bit for bit as in a full solve, with fewer supernodes") {
  GridSolve grids(9);
  const int n = grids.n;
  const cholmod_factor& L = grids.factor.L();
  const int* perm = static_cast<const int*>(L.Perm);
  const int* super = static_cast<const int*>(L.super);
  // Unit columns on a few unknowns of the first grid, wanted on those unknowns (as H^-1 on
  // the touched nodes wants them).
  const std::vector<int> rows = {3, 140, 400, 655};
  const int width = static_cast<int>(rows.size());
  MatX B = MatX::Zero(2 * n, width), X_full(2 * n, width), X(2 * n, width);
  for (int c = 0; c < width; ++c) B(rows[c], c) = 1.0;
  grids.solve.solve(L, B.data(), 2 * n, X_full.data(), 2 * n, width, grids.ws);
  const int full_supernodes = grids.ws.backward_supernodes;
  std::vector<char> wanted;
  grids.solve.mark_wanted(rows, wanted);
  REQUIRE(wanted.size() == L.nsuper);
  grids.solve.solve(L, B.data(), 2 * n, X.data(), 2 * n, width, grids.ws, wanted.data());
  for (const int r : rows)
    for (int c = 0; c < width; ++c) CHECK(X(r, c) == X_full(r, c));
  // The pass skipped supernodes, and left zero where it did.
  CHECK(grids.ws.backward_supernodes < full_supernodes);
  int skipped_nonzero = 0;
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s)
    for (int k = super[s]; k < super[s + 1]; ++k)
      for (int c = 0; c < width; ++c) {
        if (wanted[s]) CHECK(X(perm[k], c) == X_full(perm[k], c));  // ancestors: exact too
        else skipped_nonzero += X(perm[k], c) != 0.0;
      }
  CHECK(skipped_nonzero == 0);
  // The mask holds each wanted row's supernode and every ancestor: an ancestor's rows are
  // rows of L below a wanted supernode's triangle, and they are wanted.
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s) {
    if (!wanted[s]) continue;
    const SupernodeView view = supernode_view(L, s);
    for (int r = view.columns; r < view.height; ++r) {
      int owner = 0;
      while (super[owner + 1] <= view.rows[r]) ++owner;
      CHECK(wanted[owner]);
    }
  }
}

TEST_CASE("supernodal block solve: the AVX2 kernels give the baseline kernels' bits, at every block width") {
  GridSolve grids(7);
  const int n = 2 * grids.n;
  const cholmod_factor& L = grids.factor.L();
  // The kernels take a supernode's columns two at a time, then the odd one left: a
  // supernode of 3, 5, ... columns with rows below its triangle runs both branches.
  bool both_branches = false;
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s) {
    const SupernodeView view = supernode_view(L, s);
    both_branches = both_branches || (view.columns >= 3 && view.columns % 2 == 1 && view.height > view.columns);
  }
  REQUIRE(both_branches);
  if (!use_avx2()) WARN_MESSAGE(false, "this CPU has no AVX2: both runs below take the baseline kernels");
  for (int width = 1; width <= SupernodalBlockSolve::kMaxWidth; ++width) {
    CAPTURE(width);
    const MatX B = MatX::Random(n, width);
    MatX X_vector(n, width), X_baseline(n, width);
    grids.solve.solve(L, B.data(), n, X_vector.data(), n, width, grids.ws);
    {
      const BaselineKernelsOnly baseline;
      REQUIRE_FALSE(use_avx2());
      grids.solve.solve(L, B.data(), n, X_baseline.data(), n, width, grids.ws);
    }
    CHECK(std::memcmp(X_vector.data(), X_baseline.data(), sizeof(double) * X_vector.size()) == 0);
    CHECK((grids.A * X_vector - B).norm() <= 1e-12 * B.norm());
  }
}
