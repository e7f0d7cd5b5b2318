// RowColumnCache: y_i = H^-1 J_i^T per row, solved once per factorisation for a row whose
// stencil does not change, solved again when it does; the Delassus matrix built from the
// cached columns equals J H^-1 J^T; energy rows from node columns equal them too.
#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "engine/constraints/delassus.hpp"
#include "engine/constraints/row_column_cache.hpp"
#include "engine/step/stages.hpp"
#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;

namespace {

constexpr int kNodes = 12;  // node 0 fixed: 33 free DOFs

struct Fixture {
  std::vector<int> free_index;
  MatX H;
  Eigen::LLT<MatX> llt;
  RowTable rows;
  int solves = 0;  // columns solve_many was asked for

  Fixture() {
    std::mt19937 rng(3);
    std::normal_distribution<double> normal;
    for (int n = 0; n < kNodes; ++n) free_index.push_back(n - 1);
    const int dofs = 3 * (kNodes - 1);
    MatX B(dofs, dofs);
    for (int i = 0; i < dofs; ++i)
      for (int j = 0; j < dofs; ++j) B(i, j) = normal(rng);
    H = B * B.transpose() + dofs * MatX::Identity(dofs, dofs);
    llt.compute(H);
    // 20 rows over 2 to 4 consecutive nodes (wrapping, so some include the fixed node 0).
    for (int i = 0; i < 20; ++i) {
      rows.add_row(RowKind::Contact, 0, 0, 1e300, 100 + i);
      for (int k = 0; k < 2 + i % 3; ++k) rows.add_entry((i + k) % kNodes, Vec3(normal(rng), normal(rng), normal(rng)));
    }
  }
  int dofs() const { return static_cast<int>(H.rows()); }
  MatX jacobian() const {
    MatX J = MatX::Zero(rows.size(), dofs());
    for (int i = 0; i < rows.size(); ++i)
      for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
        if (const int f = free_index[rows.nodes[e]]; f >= 0) J.block<1, 3>(i, 3 * f) += rows.jac[e].transpose();
    return J;
  }
  int fill(RowColumnCache& cache, std::vector<const double*>& columns, int node_budget = 0) {
    return cache.columns(rows, free_index, dofs(), [this](const auto& B, auto& X, const std::vector<int>*, const ZeroedColumns::Pattern*) {
      solves += static_cast<int>(B.cols());
      X = llt.solve(B);
    }, columns, node_budget);
  }
  // Largest |y_i - H^-1 J_i^T| over the rows, relative to the largest column entry.
  double column_error(const std::vector<const double*>& columns) const {
    const MatX Y = llt.solve(MatX(jacobian().transpose()));
    double error = 0;
    for (int i = 0; i < rows.size(); ++i)
      error = std::max(error, (Eigen::Map<const VecX>(columns[i], dofs()) - Y.col(i)).lpNorm<Eigen::Infinity>());
    return error / Y.lpNorm<Eigen::Infinity>();
  }
};

}  // namespace

TEST_CASE("row_column_cache: columns are H^-1 J^T, solved once while the stencils stay") {
  Fixture p;
  RowColumnCache cache;
  std::vector<const double*> columns;
  CHECK(p.fill(cache, columns) == 20);
  CHECK(p.solves == 20);
  // A dense LLT solve of a well-conditioned 33 x 33 system: round-off, far below 1e-12.
  CHECK(p.column_error(columns) < 1e-12);

  CHECK(p.fill(cache, columns) == 0);  // nothing changed: nothing solved
  CHECK(p.solves == 20);
  CHECK(p.column_error(columns) < 1e-12);

  // One row's Jacobian changes a little: that row alone is solved again.
  p.rows.jac[p.rows.begin[7]][1] += 1e-9;
  CHECK(p.fill(cache, columns) == 1);
  CHECK(p.column_error(columns) < 1e-12);
  // A row whose stencil has another node: solved again too.
  p.rows.nodes[p.rows.begin[4]] = (p.rows.nodes[p.rows.begin[4]] + 6) % kNodes;
  CHECK(p.fill(cache, columns) == 1);
  CHECK(p.column_error(columns) < 1e-12);

  cache.reset();  // a new factorisation
  CHECK(p.fill(cache, columns) == 20);
}

TEST_CASE("row_column_cache: W built from the cached columns equals J H^-1 J^T") {
  Fixture p;
  RowColumnCache cache;
  std::vector<const double*> columns;
  p.fill(cache, columns);
  p.rows.jac[p.rows.begin[2]][0] *= 2;
  p.fill(cache, columns);  // 19 kept, 1 solved again
  Delassus W;
  W.build_direct(p.rows, p.free_index, columns);
  const MatX J = p.jacobian();
  const MatX expected = J * p.llt.solve(MatX(J.transpose()));
  CHECK((W.matrix() - expected).lpNorm<Eigen::Infinity>() < 1e-12 * expected.lpNorm<Eigen::Infinity>());
  for (int i = 0; i < p.rows.size(); ++i) CHECK(W.diagonal(i) == doctest::Approx(expected(i, i)).epsilon(1e-12));
}

TEST_CASE("row_column_cache: two rows with one key never share a column") {
  Fixture p;
  p.rows.key[5] = p.rows.key[6];  // a duplicate key (not made by the engine's row builders)
  RowColumnCache cache;
  std::vector<const double*> columns;
  p.fill(cache, columns);
  CHECK(p.column_error(columns) < 1e-12);
  CHECK(p.fill(cache, columns) >= 1);  // one of the two is not in the cache, and is solved again
  CHECK(p.column_error(columns) < 1e-12);
}

TEST_CASE("row_column_cache: columns of rows no longer seen are dropped once they outnumber the rows") {
  Fixture p;
  RowColumnCache cache;
  std::vector<const double*> columns;
  p.fill(cache, columns);
  CHECK(cache.size() == 20);
  // The same stencils under new keys (as when contacts move to other vertices): 20 solved,
  // and the 20 old entries, unused by this call, are dropped.
  for (auto& key : p.rows.key) key += 1000;
  CHECK(p.fill(cache, columns) == 20);
  CHECK(cache.size() == 20);
  CHECK(p.column_error(columns) < 1e-12);
}

TEST_CASE("row_column_cache: a new factorisation of the step system empties the cache") {
  using namespace sinew::test;
  World world = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 1e-3));
  REQUIRE(world.step());
  State& state = world.mutable_state();
  RowTable rows;
  rows.add_row(RowKind::Contact, 0, 0, 1e300, 1);
  rows.add_entry(world.model().num_nodes - 1, Vec3(0, 1, 0));
  LinearSolver solver(world.model().solver);
  REQUIRE(factorize_step_system(world.model(), solver, state));
  std::vector<const double*> columns;
  const int dofs = 3 * world.model().num_free;
  state.row_columns.columns(rows, world.model().free_index, dofs, [&](const auto& B, auto& X, const std::vector<int>*, const ZeroedColumns::Pattern*) { solver.solve_many(B, X); },
                            columns);
  REQUIRE(state.row_columns.size() == 1);
  REQUIRE(factorize_step_system(world.model(), solver, state));
  CHECK(state.row_columns.size() == 0);
}

TEST_CASE("row_column_cache: energy rows from node columns are H^-1 J^T and cost no solve while their nodes stay") {
  constexpr int kBudget = 24;  // node columns per energy row: room for every case below
  Fixture p;
  // Rows 0-5 become energy rows: rows 0-4 span nodes 0-6 (node 0 fixed: 6 free nodes).
  for (int i = 0; i < 6; ++i) p.rows.kind[i] = RowKind::Energy;
  RowTable first_rows = p.rows;
  p.rows.kind[5] = RowKind::Contact;  // row 5 (nodes 5-8) joins the energy rows later
  RowColumnCache cache;
  std::vector<const double*> columns;
  // First call after a factorisation: the 15 other rows one column each, the energy rows'
  // 6 free nodes 3 columns each, no energy row solved on its own.
  CHECK(p.fill(cache, columns, kBudget) == 15 + 3 * 6);
  CHECK(p.solves == 15 + 3 * 6);  // what solve_many was asked for, not only what the cache says
  CHECK(cache.node_count() == 6);
  CHECK(p.column_error(columns) < 1e-12);
  // The energy rows' Jacobians move (as at every SQP iteration): nothing solved, still exact.
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 5; ++i)
    for (int e = p.rows.begin[i]; e < p.rows.begin[i + 1]; ++e) p.rows.jac[e] += 0.1 * Vec3(normal(rng), normal(rng), normal(rng));
  CHECK(p.fill(cache, columns, kBudget) == 0);
  CHECK(p.solves == 15 + 3 * 6);
  // 1e-12 as for solved columns: each is a sum of at most 4 node columns times a Jacobian of
  // the same size as the column's entries, a few round-offs of an LLT solve.
  CHECK(p.column_error(columns) < 1e-12);
  // An energy row reaching nodes without columns (row 5: nodes 7, 8) is solved on its own,
  // and no node columns are added before the next factorisation.
  p.rows.kind[5] = RowKind::Energy;
  p.rows.jac[p.rows.begin[5]] *= 2;
  CHECK(p.fill(cache, columns, kBudget) == 1);
  CHECK(cache.node_count() == 6);
  CHECK(p.column_error(columns) < 1e-12);
  // W from a mix of kept, solved and node-derived columns equals J H^-1 J^T.
  Delassus W;
  W.build_direct(p.rows, p.free_index, columns);
  const MatX J = p.jacobian();
  const MatX expected = J * p.llt.solve(MatX(J.transpose()));
  CHECK((W.matrix() - expected).lpNorm<Eigen::Infinity>() < 1e-12 * expected.lpNorm<Eigen::Infinity>());
  // A new factorisation: the node columns go with the row columns and are chosen afresh.
  cache.reset();
  CHECK(cache.node_count() == 0);
  CHECK(p.fill(cache, columns, kBudget) == 14 + 3 * 8);  // 6 energy rows now, on nodes 1-8
  CHECK(p.column_error(columns) < 1e-12);
  // Without node columns energy rows are rows like any other.
  RowColumnCache plain;
  Fixture q;
  q.rows = first_rows;
  CHECK(q.fill(plain, columns) == 20);
  CHECK(plain.node_count() == 0);
  // Over budget (18 node columns for 5 energy rows, 3 allowed per row): solved per row.
  RowColumnCache tight;
  Fixture t;
  t.rows = first_rows;
  t.rows.kind[5] = RowKind::Contact;
  CHECK(t.fill(tight, columns, 3) == 20);
  CHECK(tight.node_count() == 0);
  CHECK(t.column_error(columns) < 1e-12);
  // A first call without energy rows chooses no nodes: later energy rows are solved per row
  // until the next factorisation.
  RowColumnCache later;
  Fixture u;
  u.rows = first_rows;
  for (int i = 0; i < 6; ++i) u.rows.kind[i] = RowKind::Contact;
  CHECK(u.fill(later, columns, kBudget) == 20);
  u.rows.kind[0] = RowKind::Energy;
  u.rows.jac[u.rows.begin[0]] *= 2;
  CHECK(u.fill(later, columns, kBudget) == 1);
  CHECK(later.node_count() == 0);
  CHECK(u.column_error(columns) < 1e-12);
}

namespace {

// The rows of `rows` listed in `order`, in that order.
RowTable rows_in_order(const RowTable& rows, const std::vector<int>& order) {
  RowTable out;
  for (const int i : order) {
    out.add_row(rows.kind[i], rows.value[i], rows.lo[i], rows.hi[i], rows.key[i]);
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e) out.add_entry(rows.nodes[e], rows.jac[e]);
  }
  return out;
}

}  // namespace

TEST_CASE("row_column_cache: the same columns as the previous call only when W = J Y cannot have changed") {
  constexpr int kBudget = 24;
  Fixture p;
  RowColumnCache cache;
  std::vector<const double*> columns;
  p.fill(cache, columns);
  CHECK_FALSE(cache.same_columns_as_previous_call());  // everything solved
  p.fill(cache, columns);
  CHECK(cache.same_columns_as_previous_call());  // nothing changed
  // W built at the first call still equals J H^-1 J^T: what the solver relies on to skip it.
  Delassus W;
  W.build_direct(p.rows, p.free_index, columns);
  p.fill(cache, columns);
  REQUIRE(cache.same_columns_as_previous_call());
  const MatX J = p.jacobian();
  const MatX expected = J * p.llt.solve(MatX(J.transpose()));
  CHECK((W.matrix() - expected).lpNorm<Eigen::Infinity>() < 1e-12 * expected.lpNorm<Eigen::Infinity>());
  // One Jacobian entry moves: solved again, not the same.
  p.rows.jac[p.rows.begin[3]][2] += 1e-9;
  p.fill(cache, columns);
  CHECK_FALSE(cache.same_columns_as_previous_call());
  p.fill(cache, columns);
  CHECK(cache.same_columns_as_previous_call());
  // The same rows in another order: W's rows and columns are permuted.
  const RowTable forward = p.rows;
  std::vector<int> order(forward.size());
  for (int i = 0; i < forward.size(); ++i) order[i] = forward.size() - 1 - i;
  p.rows = rows_in_order(forward, order);
  p.fill(cache, columns);
  CHECK_FALSE(cache.same_columns_as_previous_call());
  p.rows = forward;
  p.fill(cache, columns);
  CHECK_FALSE(cache.same_columns_as_previous_call());
  // A row fewer: not the same rows.
  order.resize(forward.size() - 1);
  for (int i = 0; i + 1 < forward.size(); ++i) order[i] = i;
  p.rows = rows_in_order(forward, order);
  p.fill(cache, columns);
  CHECK_FALSE(cache.same_columns_as_previous_call());
  p.rows = forward;
  p.fill(cache, columns);
  // A new factorisation: nothing is the same.
  p.fill(cache, columns);
  REQUIRE(cache.same_columns_as_previous_call());
  cache.reset();
  p.fill(cache, columns);
  CHECK_FALSE(cache.same_columns_as_previous_call());
  // Energy rows derived from node columns are derived anew at every call: never the same,
  // and a call after one that derived them is not the same either, even when it keeps
  // every column (its kept entry may be older than the derived column W used).
  RowColumnCache energy;
  Fixture q;
  for (int i = 0; i < 3; ++i) q.rows.kind[i] = RowKind::Energy;
  q.fill(energy, columns, kBudget);
  q.fill(energy, columns, kBudget);
  CHECK_FALSE(energy.same_columns_as_previous_call());
  // A duplicated key: the two rows cannot both hold their entry's column.
  RowColumnCache duplicates;
  Fixture d;
  d.rows.key[5] = d.rows.key[6];
  d.fill(duplicates, columns);
  d.fill(duplicates, columns);
  d.fill(duplicates, columns);
  CHECK_FALSE(duplicates.same_columns_as_previous_call());
}

TEST_CASE("row_column_cache: a call may be skipped only for the last call's rows, bit for bit, before any reset") {
  Fixture p;
  RowColumnCache cache;
  std::vector<const double*> columns;
  CHECK_FALSE(cache.repeats_last_call(p.rows));  // no call yet
  p.fill(cache, columns);
  CHECK(cache.repeats_last_call(p.rows));
  // What skipping keeps: a call now solves nothing and gives the very columns, bit for bit,
  // that the last call's pointers hold.
  std::vector<const double*> again;
  CHECK(p.fill(cache, again) == 0);
  REQUIRE(again.size() == columns.size());
  for (size_t i = 0; i < columns.size(); ++i)
    CHECK(Eigen::Map<const VecX>(again[i], p.dofs()) == Eigen::Map<const VecX>(columns[i], p.dofs()));
  CHECK(cache.repeats_last_call(p.rows));
  // One Jacobian entry moves by one ulp: not the same rows.
  const RowTable original = p.rows;
  double& entry = p.rows.jac[p.rows.begin[9]][0];
  entry = std::nextafter(entry, 1e300);
  CHECK_FALSE(cache.repeats_last_call(p.rows));
  // Another node in a stencil, another key, the rows in another order, a row fewer.
  p.rows = original;
  p.rows.nodes[p.rows.begin[2]] = (p.rows.nodes[p.rows.begin[2]] + 5) % kNodes;
  CHECK_FALSE(cache.repeats_last_call(p.rows));
  p.rows = original;
  p.rows.key[11] += 1000;
  CHECK_FALSE(cache.repeats_last_call(p.rows));
  std::vector<int> order(original.size());
  for (int i = 0; i < original.size(); ++i) order[i] = original.size() - 1 - i;
  CHECK_FALSE(cache.repeats_last_call(rows_in_order(original, order)));
  order.resize(original.size() - 1);
  for (int i = 0; i + 1 < original.size(); ++i) order[i] = i;
  CHECK_FALSE(cache.repeats_last_call(rows_in_order(original, order)));
  // The rows again: yes, until a new factorisation.
  p.rows = original;
  CHECK(cache.repeats_last_call(p.rows));
  cache.reset();
  CHECK_FALSE(cache.repeats_last_call(p.rows));
  p.fill(cache, columns);
  CHECK(cache.repeats_last_call(p.rows));
  // A copy (a State copied from another World) or a moved-to cache: the columns pointers
  // point into the original, so its first call must not be skipped.
  RowColumnCache copy = cache;
  CHECK_FALSE(copy.repeats_last_call(p.rows));
  RowColumnCache assigned;
  assigned = cache;
  CHECK_FALSE(assigned.repeats_last_call(p.rows));
  RowColumnCache moved = std::move(copy);
  CHECK_FALSE(moved.repeats_last_call(p.rows));
  CHECK(cache.repeats_last_call(p.rows));  // the original still may
}

TEST_CASE("row_column_cache: partial columns, right on the stencils seen so far, give W = J H^-1 J^T") {
  constexpr int kBudget = 24;
  Fixture p;
  for (int i = 0; i < 3; ++i) p.rows.kind[i] = RowKind::Energy;  // rows 0-2 from node columns
  // A partial solve: X right on the wanted rows only, NaN elsewhere, so that any read of a
  // column off the stencils it was solved for shows in W.
  std::vector<int> wanted_seen;
  const auto partial_solve = [&](const auto& B, auto& X, const std::vector<int>* wanted, const ZeroedColumns::Pattern*) {
    REQUIRE(wanted);
    wanted_seen = *wanted;
    const MatX full = p.llt.solve(B);
    X.setConstant(std::numeric_limits<double>::quiet_NaN());
    for (const int r : *wanted) X.row(r) = full.row(r);
  };
  const auto expected_W = [](const Fixture& f, const RowTable& rows) {
    Fixture g = f;
    g.rows = rows;
    const MatX J = g.jacobian();
    return MatX(J * f.llt.solve(MatX(J.transpose())));
  };
  // Call 1: the first 5 rows, on nodes 0-6 (node 0 fixed: 18 of the 33 free DOFs).
  RowTable first;
  for (int i = 0; i < 5; ++i) {
    first.add_row(p.rows.kind[i], 0, 0, 1e300, p.rows.key[i]);
    for (int e = p.rows.begin[i]; e < p.rows.begin[i + 1]; ++e) first.add_entry(p.rows.nodes[e], p.rows.jac[e]);
  }
  RowColumnCache cache;
  std::vector<const double*> columns;
  cache.columns(first, p.free_index, p.dofs(), partial_solve, columns, kBudget, true);
  CHECK_FALSE(cache.complete());
  CHECK(wanted_seen.size() == 18);  // the rest of X was left out
  Delassus W;
  W.build_direct(first, p.free_index, columns, nullptr, &cache.generations());
  const MatX W1 = expected_W(p, first);
  CHECK((W.matrix() - W1).lpNorm<Eigen::Infinity>() < 1e-12 * W1.lpNorm<Eigen::Infinity>());
  // Call 2: all 20 rows, the first 5 kept (and the energy rows derived), 15 new ones, most
  // on stencils call 1 did not want: their columns are of a later generation.
  cache.columns(p.rows, p.free_index, p.dofs(), partial_solve, columns, kBudget, true);
  CHECK(wanted_seen.size() == 33);
  const std::vector<long>& g = cache.generations();
  for (int i = 5; i < 20; ++i) CHECK(g[i] > g[0]);
  W.build_direct(p.rows, p.free_index, columns, nullptr, &g);
  const MatX W2 = expected_W(p, p.rows);
  CHECK((W.matrix() - W2).lpNorm<Eigen::Infinity>() < 1e-12 * W2.lpNorm<Eigen::Infinity>());
  // Without the generations some entries read a column off its stencils: NaN.
  Delassus unordered;
  unordered.build_direct(p.rows, p.free_index, columns);
  CHECK_FALSE(unordered.matrix().allFinite());
  // The same rows again (an SQP iteration that keeps them, whose caller skips the call) and a
  // call that wants whole columns but keeps every partial one: neither is complete, so no
  // caller takes Y beyond W (solve_constraints' whole_columns).
  CHECK(cache.repeats_last_call(p.rows));
  CHECK_FALSE(cache.complete());
  CHECK(cache.columns(p.rows, p.free_index, p.dofs(), [&](const auto&, auto&, const std::vector<int>*, const ZeroedColumns::Pattern*) { FAIL("nothing to solve"); },
                      columns, kBudget, false) == 0);
  CHECK_FALSE(cache.complete());
  // A whole solve (partial = false) of a changed row: complete columns beside partial ones.
  p.rows.jac[p.rows.begin[15]] *= 2;
  cache.columns(p.rows, p.free_index, p.dofs(), [&](const auto& B, auto& X, const std::vector<int>* wanted, const ZeroedColumns::Pattern*) {
    CHECK(wanted == nullptr);
    X = p.llt.solve(B);
  }, columns, kBudget, false);
  CHECK(cache.generations()[15] == RowColumnCache::kComplete);
  CHECK_FALSE(cache.complete());
  W.build_direct(p.rows, p.free_index, columns, nullptr, &cache.generations());
  const MatX W3 = expected_W(p, p.rows);
  CHECK((W.matrix() - W3).lpNorm<Eigen::Infinity>() < 1e-12 * W3.lpNorm<Eigen::Infinity>());
  // After a factorisation, whole columns throughout: complete.
  cache.reset();
  cache.columns(p.rows, p.free_index, p.dofs(), [&](const auto& B, auto& X, const std::vector<int>*, const ZeroedColumns::Pattern*) { X = p.llt.solve(B); },
                columns, kBudget, false);
  CHECK(cache.complete());
}

TEST_CASE("row_column_cache: a solver given B's pattern returns the columns of one that scans B") {
  // A supernodal factor (LinearSolver reads B only at the pattern's rows), through the
  // solver that reads the pattern the cache passes, against one that ignores it: the same bits.
  const SceneDesc scene = parse_scene_text(R"({"h": 0.0166667, "bodies": [{"name": "block",
      "shape": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}], "cell_size": 0.1,
      "material": {"E": 1e6, "nu": 0.3, "rho": 1000}}]})", "block", ".");  // 1,331 nodes
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  REQUIRE(world.step());
  State& state = world.mutable_state();
  const Model& model = world.model();
  RowTable rows;
  for (int i = 0; i < 12; ++i) {
    rows.add_row(RowKind::Contact, 0, 0, 1e300, 500 + i);
    for (int k = 0; k < 3; ++k) rows.add_entry((7 * i + 5 * k) % model.num_nodes, Vec3(1.0 + k, -0.5, 0.25 * i));
  }
  LinearSolver solver(model.solver);
  REQUIRE(factorize_step_system(model, solver, state));
  REQUIRE(solver.honours_wanted_rows());  // supernodal: the pattern is what B is read through
  const int dofs = 3 * model.num_free;
  RowColumnCache scanning, patterned;
  std::vector<const double*> a, b;
  int patterns = 0;
  scanning.columns(rows, model.free_index, dofs, [&](const auto& B, auto& X, const std::vector<int>* wanted,
                                                    const ZeroedColumns::Pattern*) {
    solver.solve_many(B, X, wanted);
  }, a);
  patterned.columns(rows, model.free_index, dofs,
                    [&](const auto& B, auto& X, const std::vector<int>* wanted, const ZeroedColumns::Pattern* pattern) {
                      ++patterns;
                      solver.solve_many(B, X, wanted, pattern);
                    },
                    b);
  CHECK(patterns == 1);
  for (int i = 0; i < rows.size(); ++i) CHECK(std::memcmp(a[i], b[i], sizeof(double) * dofs) == 0);
}
