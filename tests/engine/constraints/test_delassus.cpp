// H^-1 on the touched nodes and the LCP matrix W = J H^-1 J^T built from it (factored and
// dense forms) or from one solve per row: all against W formed from a dense inverse.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <Eigen/Cholesky>
#include <random>

#include "engine/constraints/delassus.hpp"
#include "engine/constraints/lcp_pgs.hpp"
#include "engine/constraints/touched_inverse.hpp"
#include "engine/core/cpu_features.hpp"
#include "engine/math/transpose_columns.hpp"
#include "tests/engine/constraints/delassus_problem.hpp"

using namespace sinew;
using namespace sinew::test;


TEST_CASE("touched inverse: G equals H^-1 on the touched nodes, symmetric") {
  std::mt19937 rng(5);
  const Problem p = random_problem(40, 25, rng);
  const Eigen::LLT<MatX> llt(p.H);
  const MatX Hinv = llt.solve(MatX::Identity(p.H.rows(), p.H.cols()));
  std::vector<int> local_node;
  const TouchedInverse inverse = touched_inverse(p, llt, local_node);
  const MatX G = inverse.block();
  CHECK(G.rows() == 3 * inverse.size());
  CHECK((G - G.transpose()).norm() == 0.0);
  double worst = 0;
  for (int a = 0; a < p.nodes; ++a)
    for (int b = 0; b < p.nodes; ++b) {
      if (local_node[a] < 0 || local_node[b] < 0) continue;
      const MatX expected = Hinv.block<3, 3>(3 * p.free_index[a], 3 * p.free_index[b]);
      worst = std::max(worst, (G.block<3, 3>(3 * local_node[a], 3 * local_node[b]) - expected).norm());
    }
  CHECK(worst < 1e-12 * Hinv.norm());
}

TEST_CASE("touched inverse: kept across a refactorisation it is marked stale until reset") {
  std::mt19937 rng(6);
  const Problem p = random_problem(12, 6, rng);
  const Eigen::LLT<MatX> llt(p.H);
  std::vector<int> local_node;
  TouchedInverse inverse = touched_inverse(p, llt, local_node);
  CHECK_FALSE(inverse.stale());
  const int nodes = inverse.size();
  inverse.keep_stale();
  CHECK(inverse.stale());
  CHECK(inverse.size() == nodes);  // the columns stay
  inverse.reset(p.nodes - 1);
  CHECK_FALSE(inverse.stale());
  CHECK(inverse.size() == 0);
}

TEST_CASE("Delassus: factored, dense and direct forms all equal J H^-1 J^T") {
  std::mt19937 rng(9);
  // Many rows on few nodes (factored form) and few rows on many nodes (dense form).
  for (const auto& [nodes, m] : {std::pair{8, 60}, std::pair{40, 12}}) {
    CAPTURE(nodes);
    const Problem p = random_problem(nodes, m, rng);
    const Eigen::LLT<MatX> llt(p.H);
    const MatX J = jacobian(p);
    const MatX expected = J * llt.solve(J.transpose());
    std::vector<int> local_node;
    const TouchedInverse inverse = touched_inverse(p, llt, local_node);
    Delassus W;
    W.build(p.rows, local_node, inverse);
    CHECK(W.dense() == (m <= 3 * inverse.size()));
    CHECK((W.matrix() - expected).norm() < 1e-12 * expected.norm());
    for (int i = 0; i < m; ++i) CHECK(W.diagonal(i) == doctest::Approx(expected(i, i)).epsilon(1e-12));

    // w = W lambda + c, then kept up to date through changed().
    std::normal_distribution<double> normal;
    VecX lambda(m), c(m);
    for (int i = 0; i < m; ++i) lambda[i] = normal(rng), c[i] = normal(rng);
    // A warm start with force on 7 rows only (not a multiple of the four columns the dense
    // start sums a pass): the rows without force add nothing, the last three still count.
    VecX sparse = VecX::Zero(m);
    for (int i = 0; i < 7; ++i) sparse[(5 * i + 1) % m] = normal(rng);
    W.start(sparse, c);
    const VecX w_sparse = expected * sparse + c;
    for (int i = 0; i < m; ++i) CHECK(W.w(i) == doctest::Approx(w_sparse[i]).epsilon(1e-10));
    W.start(lambda, c);
    lambda[3] += 0.7;
    W.changed(3, 0.7);
    const VecX w = expected * lambda + c;
    for (int i = 0; i < m; ++i) CHECK(W.w(i) == doctest::Approx(w[i]).epsilon(1e-10));
    VecX product(m);
    W.multiply(lambda, product);
    CHECK((product - expected * lambda).norm() < 1e-12 * expected.norm() * lambda.norm());

    Delassus direct;
    direct.build_direct(p.rows, p.free_index, llt.solve(J.transpose()));
    CHECK(direct.dense());
    CHECK((direct.matrix() - expected).norm() < 1e-12 * expected.norm());
    for (int i = 0; i < m; ++i) CHECK(direct.diagonal(i) == doctest::Approx(expected(i, i)).epsilon(1e-12));
  }
}

TEST_CASE("PGS through the factored Delassus operator matches PGS on the dense matrix") {
  std::mt19937 rng(2);
  Problem p = random_problem(6, 50, rng);  // 50 rows on 15 DOFs: redundant, W singular
  const Eigen::LLT<MatX> llt(p.H);
  std::vector<int> local_node;
  const TouchedInverse inverse = touched_inverse(p, llt, local_node);
  Delassus W;
  W.build(p.rows, local_node, inverse);
  REQUIRE_FALSE(W.dense());
  std::normal_distribution<double> normal;
  VecX c(p.rows.size());
  for (int i = 0; i < c.size(); ++i) c[i] = normal(rng);
  RowTable dense_rows = p.rows;
  const MatX Wd = W.matrix();
  const PgsResult a = solve_pgs(W, c, VecX::Ones(c.size()), p.rows, 40, 0);
  const PgsResult b = solve_pgs(Wd, c, dense_rows, 40, 0);
  CHECK(a.iterations == b.iterations);
  for (int i = 0; i < c.size(); ++i) CHECK(p.rows.lambda[i] == doctest::Approx(dense_rows.lambda[i]).epsilon(1e-8));
}

TEST_CASE("factored Delassus: T's columns are built for the rows with a multiplier, the rest on first change") {
  std::mt19937 rng(12);
  Problem p = random_problem(6, 40, rng);  // 40 rows on 15 DOFs: the factored form
  const Eigen::LLT<MatX> llt(p.H);
  const MatX J = jacobian(p);
  const MatX expected = J * llt.solve(J.transpose());
  std::vector<int> local_node;
  const TouchedInverse inverse = touched_inverse(p, llt, local_node);
  std::normal_distribution<double> normal;
  VecX lambda = VecX::Zero(p.rows.size()), c(p.rows.size());
  for (int i = 0; i < c.size(); ++i) c[i] = normal(rng);
  for (int i = 0; i < c.size(); i += 4) lambda[i] = std::abs(normal(rng));  // a warm start on every fourth row
  Delassus cold, warm;
  cold.build(p.rows, local_node, inverse);  // rows.lambda all 0
  for (int i = 0; i < c.size(); ++i) p.rows.lambda[i] = lambda[i];
  warm.build(p.rows, local_node, inverse);
  REQUIRE_FALSE(warm.dense());
  CHECK(cold.built_columns() == 0);
  CHECK(warm.built_columns() == 10);
  for (int i = 0; i < c.size(); ++i) {
    CHECK(warm.diagonal(i) == cold.diagonal(i));
    CHECK(warm.diagonal(i) == doctest::Approx(expected(i, i)).epsilon(1e-12));
  }
  // The same w whichever columns were built first, and right.
  cold.start(lambda, c);
  warm.start(lambda, c);
  CHECK(cold.built_columns() == 10);  // start() needs the columns with a multiplier only
  cold.changed(1, 0.5);
  warm.changed(1, 0.5);
  lambda[1] += 0.5;
  CHECK(warm.built_columns() == 11);
  const VecX w = expected * lambda + c;
  for (int i = 0; i < c.size(); ++i) {
    CHECK(warm.w(i) == cold.w(i));
    CHECK(warm.w(i) == doctest::Approx(w[i]).epsilon(1e-10));
  }
  VecX product(c.size());
  warm.multiply(lambda, product);
  CHECK((product - expected * lambda).norm() < 1e-12 * expected.norm() * lambda.norm());
  CHECK((warm.matrix() - expected).norm() < 1e-12 * expected.norm());
  CHECK(warm.built_columns() == c.size());  // matrix() needs them all
}

// Redundant rows (each row three times): the multipliers are not unique, and PGS's stop on
// the natural residual (the constraints) must still be reached and mean what it says.
TEST_CASE("PGS on redundant rows stops on the residual and meets it") {
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  const int base = 8;
  MatX B(base, base);
  for (int i = 0; i < base; ++i)
    for (int j = 0; j < base; ++j) B(i, j) = normal(rng);
  const MatX W0 = B * B.transpose() + base * MatX::Identity(base, base);
  MatX J = MatX::Zero(3 * base, base);
  for (int i = 0; i < base; ++i)
    for (int copy = 0; copy < 3; ++copy) J(3 * i + copy, i) = 1.0 + 0.1 * copy;
  const MatX W = J * W0 * J.transpose();  // rank base, size 3 base
  VecX c(3 * base);
  for (int i = 0; i < base; ++i)
    for (int copy = 0; copy < 3; ++copy) c[3 * i + copy] = (1.0 + 0.1 * copy) * (i % 2 ? 1.0 : -1.0);
  RowTable rows;
  for (int i = 0; i < 3 * base; ++i) rows.add_row(RowKind::Contact, 0, 0, 1e300, i);
  const double tolerance = 1e-9;
  const PgsResult result = solve_pgs(W, c, rows, 100000, tolerance);
  MESSAGE("redundant rows: " << result.iterations << " sweeps to a residual of " << result.residual);
  CHECK(result.iterations < 100000);
  CHECK(result.residual <= tolerance);
  CHECK(lcp_residual(W, c, rows) <= tolerance);
}

// solver.delassus_reuse: the LCP solved with W~ = J H~^-1 J^T of an earlier H~ and
// c + (W - W~) lambda_k at the last solution lambda_k, repeated (what successive SQP
// iterations do), is a splitting method for the LCP (W, c). Its fixed points are exactly
// the solutions of (W, c): 0 <= lambda _|_ W~ lambda + c + (W - W~) lambda = W lambda + c.
// It converges when 2 W~ - W is positive definite; here H~ = H + a random symmetric
// perturbation of 10 % of |H|.
TEST_CASE("LCP splitting with an approximate W converges to the exact W's solution") {
  std::mt19937 rng(11);
  Problem p = random_problem(30, 20, rng);  // 20 rows on 87 DOFs: W positive definite
  std::normal_distribution<double> normal;
  const int n = static_cast<int>(p.H.rows());
  MatX E(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) E(i, j) = normal(rng);
  E = 0.5 * (E + E.transpose());
  const MatX H_old = p.H + 0.1 * p.H.norm() / E.norm() * E;
  const Eigen::LLT<MatX> exact_llt(p.H), old_llt(H_old);
  REQUIRE(old_llt.info() == Eigen::Success);
  const MatX J = jacobian(p);
  const MatX W = J * exact_llt.solve(J.transpose()), W_old = J * old_llt.solve(J.transpose());
  REQUIRE(Eigen::LLT<MatX>(2 * W_old - W).info() == Eigen::Success);  // the premise
  VecX c(p.rows.size());
  for (int i = 0; i < c.size(); ++i) c[i] = normal(rng);  // about half the rows active
  const int m = p.rows.size();
  const auto solve = [&](const MatX& matrix, const VecX& rhs, RowTable& rows) {
    const PgsResult r = solve_pgs(matrix, rhs, rows, 100000, 1e-14);
    REQUIRE(r.residual <= 1e-14);
  };
  RowTable exact_rows = p.rows;
  solve(W, c, exact_rows);
  const Eigen::Map<const VecX> exact(exact_rows.lambda.data(), m);
  REQUIRE(exact.norm() > 0);

  RowTable rows = p.rows;  // lambda = 0
  const Eigen::Map<const VecX> lambda(rows.lambda.data(), m);
  double error = exact.norm();
  int iterations = 0;
  for (; iterations < 60 && error > 1e-10 * exact.norm(); ++iterations) {
    const VecX shifted = c + (W - W_old) * lambda;
    solve(W_old, shifted, rows);
    error = (lambda - exact).norm();
  }
  MESSAGE("splitting: " << iterations << " iterations to |lambda - lambda*| = " << error << " (|lambda*| "
                        << exact.norm() << ")");
  CHECK(error <= 1e-10 * exact.norm());
  CHECK(lcp_residual(W, c, rows) <= 1e-9 * c.norm());
}

TEST_CASE("Delassus from row columns: rows on different bodies meet in zeros that are not summed") {
  // Two bodies of 4 and 5 free nodes (node 0 fixed), H block-diagonal as no element spans two
  // bodies; rows on one body or the other, and two on both (a contact between them).
  std::mt19937 rng(5);
  Problem p = random_problem(10, 30, rng);
  const std::vector<int> node_body = {0, 0, 0, 0, 0, 1, 1, 1, 1, 1};
  const int dofs = static_cast<int>(p.H.rows());
  for (int a = 0; a < dofs; ++a)
    for (int b = 0; b < dofs; ++b)
      if (node_body[a / 3 + 1] != node_body[b / 3 + 1]) p.H(a, b) = 0;
  // random_problem's rows span random nodes: make each a one-body row, but rows 0 and 1.
  RowTable rows;
  std::uniform_int_distribution<int> first(0, 4), second(5, 9);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 30; ++i) {
    rows.add_row(RowKind::Contact, 0, 0, 1e300, i);
    const bool both = i < 2, on_second = i % 2 == 1;
    const int a = both || !on_second ? first(rng) : second(rng);
    rows.add_entry(a, Vec3(normal(rng), normal(rng), normal(rng)));
    const int b = both || on_second ? second(rng) : first(rng);
    if (b != a) rows.add_entry(b, Vec3(normal(rng), normal(rng), normal(rng)));
  }
  p.rows = rows;
  const Eigen::LLT<MatX> llt(p.H);
  const MatX J = jacobian(p);
  const MatX Y = llt.solve(J.transpose());
  std::vector<const double*> columns(30);
  for (int i = 0; i < 30; ++i) columns[i] = Y.col(i).data();

  Delassus summed, masked;
  summed.build_direct(p.rows, p.free_index, columns);
  masked.build_direct(p.rows, p.free_index, columns, &node_body);
  CHECK(summed.zero_entries() == 0);
  // The pairs of rows on no common body (the fixed node 0 adds none), counted from the rows:
  // about 14 x 14, even rows being on body 0 and odd ones on body 1, rows 0 and 1 on both.
  std::vector<int> bodies(30, 0);
  for (int i = 0; i < 30; ++i)
    for (int e = p.rows.begin[i]; e < p.rows.begin[i + 1]; ++e)
      if (p.free_index[p.rows.nodes[e]] >= 0) bodies[i] |= 1 << node_body[p.rows.nodes[e]];
  long apart = 0;
  for (int j = 0; j < 30; ++j)
    for (int i = j; i < 30; ++i) apart += (bodies[i] & bodies[j]) == 0;
  CHECK(apart >= 150);  // enough pairs apart for the check to mean something
  CHECK(masked.zero_entries() == apart);
  CHECK(masked.summed_entries() + masked.zero_entries() == 30 * 31 / 2);
  // The same W, bit for bit: the entries left out are sums of exact zeros.
  CHECK((masked.matrix() - summed.matrix()).cwiseAbs().maxCoeff() == 0.0);
  const MatX expected = J * Y;
  CHECK((masked.matrix() - expected).norm() < 1e-12 * expected.norm());
}

TEST_CASE("Delassus: rebuilt with the same G and rows it keeps W; a changed Jacobian or G is taken") {
  // build() keeps W (or T's built columns) when G's version and the rows' stencils and
  // Jacobians are the last build's; every other build must equal a build from scratch.
  std::mt19937 rng(21);
  for (const auto& [nodes, m] : {std::pair{8, 60}, std::pair{40, 12}}) {
    CAPTURE(nodes);
    Problem p = random_problem(nodes, m, rng);
    const Eigen::LLT<MatX> llt(p.H);
    std::vector<int> local_node;
    TouchedInverse inverse = touched_inverse(p, llt, local_node);
    Delassus W;
    W.build(p.rows, local_node, inverse);
    const MatX first = W.matrix();
    W.build(p.rows, local_node, inverse);
    CHECK(W.matrix() == first);
    auto fresh = [&](const TouchedInverse& G) {
      Delassus D;
      D.build(p.rows, local_node, G);
      return D.matrix();
    };
    // One Jacobian entry on a free node moved: W follows it.
    int moved = 0;
    while (local_node[p.rows.nodes[moved]] < 0) ++moved;
    p.rows.jac[moved] *= 1.5;
    W.build(p.rows, local_node, inverse);
    CHECK(W.matrix() == fresh(inverse));
    CHECK(W.matrix() != first);
    // A new H, G refilled in the same object (same size, same storage): W follows it.
    const MatX H2 = p.H + MatX::Identity(p.H.rows(), p.H.cols());
    const Eigen::LLT<MatX> llt2(H2);
    const MatX before = W.matrix();
    inverse.reset(p.nodes - 1);
    std::vector<int> free_nodes;
    for (const int n : p.rows.nodes) free_nodes.push_back(p.free_index[n]);
    inverse.require(free_nodes, [&](const auto& B, auto& X, const std::vector<int>&, const ZeroedColumns::Pattern*) {
      X = llt2.solve(B);
    });
    for (int n = 0; n < p.nodes; ++n)
      if (p.free_index[n] >= 0) local_node[n] = inverse.local(p.free_index[n]);
    W.build(p.rows, local_node, inverse);
    const MatX J = jacobian(p);
    const MatX expected = J * llt2.solve(J.transpose());
    CHECK(W.matrix() == fresh(inverse));
    CHECK(W.matrix() != before);
    CHECK((W.matrix() - expected).norm() < 1e-12 * expected.norm());
  }
}

TEST_CASE("factored Delassus: a row's entries against transposed columns of T are entry()'s bit for bit") {
  std::mt19937 rng(21);
  const Problem p = random_problem(9, 70, rng);  // rows of 1-4 nodes, some on the fixed node
  const Eigen::LLT<MatX> llt(p.H);
  std::vector<int> local_node;
  const TouchedInverse inverse = touched_inverse(p, llt, local_node);
  Delassus W;
  W.build(p.rows, local_node, inverse);
  REQUIRE(!W.dense());
  const int m = p.rows.size(), k3 = W.touched_dofs();
  // Every column of T, transposed (the active set's layout), in a scattered slot order.
  std::vector<int> slot_row(m);
  for (int b = 0; b < m; ++b) slot_row[b] = (b * 37) % m;
  std::vector<const double*> columns(m);
  for (int b = 0; b < m; ++b) {
    W.ensure_column(slot_row[b]);
    columns[b] = W.built_column(slot_row[b]);
  }
  const long stride = m + 3;  // wider than the slots, as the active set's is
  // Both kernels' paths: AVX2 (where the CPU has it) and the baseline.
  for (const bool baseline : {false, true}) {
    CAPTURE(baseline);
    std::optional<BaselineKernelsOnly> off;
    if (baseline) off.emplace();
    std::vector<double> transposed(static_cast<std::size_t>(k3) * stride, std::nan(""));
    transpose_columns(columns.data(), m, k3, transposed.data(), stride);
    for (int d = 0; d < k3; ++d)
      for (int b = 0; b < m; ++b) REQUIRE(transposed[d * stride + b] == columns[b][d]);
    int differing = 0;
    for (int i = 0; i < m; ++i) {
      std::vector<double> row(m, 0.0);
      W.add_row_entries(i, transposed.data(), stride, m, row.data());
      for (int b = 0; b < m; ++b) {
        const double expected = W.entry(i, slot_row[b]);
        differing += std::memcmp(&row[b], &expected, sizeof expected) != 0;
      }
    }
    CHECK(differing == 0);
    // From a slot offset, as extend_block asks for the new slots only.
    std::vector<double> tail(m - 5, 0.0);
    W.add_row_entries(4, transposed.data() + 5, stride, m - 5, tail.data());
    for (int b = 5; b < m; ++b) CHECK(tail[b - 5] == W.entry(4, slot_row[b]));
  }
}
