// PGS on the active set with W_AA formed (lcp_active_set.hpp) against PGS over every row on
// the factored W: the same LCP, the same stopping test over every row (lcp_residual on W
// formed whole: the weighted natural residual, computed independently of either solver).
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cstring>
#include <random>

#include "engine/constraints/delassus.hpp"
#include "engine/constraints/lcp_active_set.hpp"
#include "engine/constraints/lcp_pgs.hpp"
#include "tests/engine/constraints/delassus_problem.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

struct Lcp {
  Problem problem;
  std::vector<int> local_node;
  TouchedInverse inverse;
  VecX c, weight;
};

// The touched inverse for the problem's rows and its W formed whole.
MatX prepare(Lcp& lcp) {
  const Eigen::LLT<MatX> llt(lcp.problem.H);
  lcp.inverse = touched_inverse(lcp.problem, llt, lcp.local_node);
  const MatX J = jacobian(lcp.problem);
  return J * llt.solve(J.transpose());
}

// A factored LCP: `rows` rows on `nodes` nodes (node 0 fixed), with a solution by
// construction (W singular: a random c may have none): c = w* - W lambda*, lambda* > 0 on
// about `pressed` of the rows, w* > 0 on the others; weights of either kind's scale. With
// fewer pressed rows than DOFs the active set stays below T's height, where it is used.
Lcp random_lcp(int nodes, int rows, double pressed, std::mt19937& rng) {
  Lcp lcp;
  lcp.problem = random_problem(nodes, rows, rng);
  const MatX W = prepare(lcp);
  std::uniform_real_distribution<double> unit(0.0, 1.0), scale(0.5, 2.0);
  VecX lambda_star = VecX::Zero(rows), w_star = VecX::Zero(rows);
  for (int i = 0; i < rows; ++i) (unit(rng) < pressed ? lambda_star[i] : w_star[i]) = scale(rng);
  lcp.c = w_star - W * lambda_star;
  lcp.weight.resize(rows);
  for (int i = 0; i < rows; ++i) lcp.weight[i] = scale(rng);
  return lcp;
}

}  // namespace

TEST_CASE("active-set PGS: the factored LCP's solution, every row within the tolerance") {
  std::mt19937 rng(21);
  for (const bool warm : {false, true}) {
    CAPTURE(warm);
    Lcp lcp = random_lcp(30, 150, 0.25, rng);  // 150 rows on 87 DOFs: W singular
    RowTable& rows = lcp.problem.rows;
    if (warm)  // a warm start on every third row, some of which will have to let go
      for (int i = 0; i < rows.size(); i += 3) rows.lambda[i] = 0.1;
    RowTable all_rows = rows;
    Delassus W, W_all;
    W.build(rows, lcp.local_node, lcp.inverse);
    W_all.build(all_rows, lcp.local_node, lcp.inverse);
    REQUIRE_FALSE(W.dense());
    const double tolerance = 1e-10;
    ActiveSetPgs active;
    const PgsResult a = active.solve(W, lcp.c, lcp.weight, rows, 200000, tolerance, 8);
    const PgsResult b = solve_pgs(W_all, lcp.c, lcp.weight, all_rows, 200000, tolerance, 8);
    MESSAGE("active set: " << a.iterations << " sweeps, " << active.active_rows() << " of " << rows.size()
                           << " rows in A after " << active.rounds() << " rounds; every row: " << b.iterations << " sweeps");
    CHECK(active.rounds() >= 1);  // it did sweep on A (not on T throughout)
    CHECK(active.active_rows() < rows.size());  // the point: some rows are never swept there
    CHECK(a.residual <= tolerance);
    CHECK(b.residual <= tolerance);
    const MatX Wm = W.matrix();
    CHECK(lcp_residual(Wm, lcp.c, rows, &lcp.weight) <= 1.01 * tolerance);  // round-off of w only
    int carrying = 0;
    for (int i = 0; i < rows.size(); ++i)
      if (rows.lambda[i] != 0) {
        ++carrying;
        CHECK(active.in_active(i));  // no row outside A carries force
      }
    CHECK(carrying > 0);
    // W lambda is the same at every solution of a PSD LCP (lambda need not be, W singular);
    // at residuals of 1e-10 the two agree to about its square root.
    const Eigen::Map<const VecX> la(rows.lambda.data(), rows.size()), lb(all_rows.lambda.data(), rows.size());
    CHECK((Wm * (la - lb)).norm() <= 1e-4 * lcp.c.norm());
  }
}

TEST_CASE("active-set PGS: one instance reused across sizes, A growing over rounds") {
  std::mt19937 rng(24);
  ActiveSetPgs active;  // its storage (W_AA's stride, the per-row maps) carries over
  int grew = 0;
  for (const auto& [nodes, m] : {std::pair{30, 150}, std::pair{12, 60}, std::pair{40, 220}, std::pair{20, 90},
                                 std::pair{40, 200}}) {
    CAPTURE(m);
    Lcp lcp = random_lcp(nodes, m, 0.3, rng);
    RowTable& rows = lcp.problem.rows;
    Delassus W;
    W.build(rows, lcp.local_node, lcp.inverse);
    REQUIRE_FALSE(W.dense());
    const double tolerance = 1e-10;
    const PgsResult result = active.solve(W, lcp.c, lcp.weight, rows, 200000, tolerance, 8);
    CHECK(result.residual <= tolerance);
    CHECK(lcp_residual(W.matrix(), lcp.c, rows, &lcp.weight) <= 1.01 * tolerance);
    grew += active.rounds() > 1;
    // W_AA as formed over the rounds (rows joining, its stride growing from the last solve's):
    // every entry entry()'s bits for the row that joined first, both halves, W_ii on the
    // diagonal.
    if (active.rounds() == 0) continue;
    std::vector<int> in_a;
    for (int i = 0; i < m; ++i)
      if (active.in_active(i)) in_a.push_back(i);
    int differing = 0;
    for (const int i : in_a)
      for (const int j : in_a) {
        const double got = active.formed_entry(i, j);
        const double expected = i == j ? W.diagonal(i) : active.joined_before(i, j) ? W.entry(i, j) : W.entry(j, i);
        differing += std::memcmp(&got, &expected, sizeof got) != 0;
      }
    CHECK(differing == 0);
  }
  MESSAGE(grew << " of 5 solves added rows to A after its first round");
  CHECK(grew >= 1);
}

TEST_CASE("active-set PGS: a contact's friction rows join with their normal row and keep its box") {
  std::mt19937 rng(22);
  std::normal_distribution<double> normal;
  Lcp lcp;
  lcp.problem = random_problem(30, 120, rng);
  RowTable& rows = lcp.problem.rows;
  // Six contacts, one on the fixed node 0 (its rows move nothing: W_ii = 0), the others on
  // free nodes: a normal row and two friction rows with mu 0.5.
  const int strain_rows = rows.size();
  for (int k = 0; k < 6; ++k) {
    const int node = k == 0 ? 0 : k;
    const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const int normal_row = rows.add_row(RowKind::Contact, 0, 0, 1e300, 1000 + k);
    rows.add_entry(node, n);
    for (const Vec3& t : {t1, t2}) {
      const int f = rows.add_row(RowKind::Friction, 0, -1e300, 1e300, 2000 + 2 * k);
      rows.normal_row[f] = normal_row;
      rows.mu[f] = 0.5;
      rows.add_entry(node, t);
    }
  }
  const int m = rows.size();
  const MatX Wm = prepare(lcp);
  // A solution by construction: a quarter of the strain rows pressed, every free contact
  // pressed (lambda_n* 1) with friction inside its box (w* 0) or on it (w* pushing outwards).
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  VecX lambda_star = VecX::Zero(m), w_star = VecX::Zero(m);
  for (int i = 0; i < strain_rows; ++i) (unit(rng) < 0.25 ? lambda_star[i] : w_star[i]) = 1.0;
  for (int i = strain_rows + 3; i < m; ++i) {
    if (rows.normal_row[i] < 0) lambda_star[i] = 1.0;
    else if ((i - strain_rows) % 3 == 2) lambda_star[i] = 0.5, w_star[i] = -0.2;  // sliding: on its box, w pushing out
    else lambda_star[i] = 0.1 * normal(rng);  // sticking: inside the box, w 0
  }
  lcp.c = w_star - Wm * lambda_star;
  lcp.weight = VecX::Ones(m);
  // The fixed contact: a friction row with a warm multiplier whose normal row has none.
  // Plain sweeps skip both (W_ii = 0), so the friction row enters A by its multiplier alone,
  // and its box needs its normal row in A too.
  rows.lambda[strain_rows + 1] = 0.01;
  Delassus W;
  W.build(rows, lcp.local_node, lcp.inverse);
  REQUIRE_FALSE(W.dense());
  const double tolerance = 1e-10;
  ActiveSetPgs active;
  const PgsResult result = active.solve(W, lcp.c, lcp.weight, rows, 200000, tolerance, 8);
  CHECK(active.rounds() >= 1);
  CHECK(active.in_active(strain_rows + 1));
  CHECK(active.in_active(strain_rows));      // its normal row, which has no multiplier
  CHECK(active.in_active(strain_rows + 2));  // and its sibling
  CHECK(result.residual <= tolerance);
  CHECK(lcp_residual(Wm, lcp.c, rows, &lcp.weight) <= 1.01 * tolerance);
  int sliding = 0;
  for (int i = strain_rows + 3; i < m; ++i) {
    if (rows.normal_row[i] < 0) {
      CHECK(rows.lambda[i] > 0);  // every free contact carries force
      continue;
    }
    const int normal_row = rows.normal_row[i];
    CHECK(active.in_active(normal_row));
    const double box = 0.5 * rows.lambda[normal_row];
    CHECK(std::abs(rows.lambda[i]) <= box * (1 + 1e-12));
    sliding += std::abs(rows.lambda[i]) >= box * (1 - 1e-9);
  }
  MESSAGE(sliding << " of 10 free friction rows on their box");
  CHECK(sliding >= 1);
}

TEST_CASE("active-set PGS: its sweeps stay within the cap and it reports the residual of every row") {
  std::mt19937 rng(23);
  // 5: one sweep left after the plain ones (too few to form W_AA); 10: a short round on A;
  // 36, 37: a round boundary (4 plain sweeps + 32); 100: several rounds.
  for (const int cap : {5, 10, 36, 37, 100}) {
    CAPTURE(cap);
    Lcp lcp = random_lcp(30, 150, 0.25, rng);
    RowTable& rows = lcp.problem.rows;
    Delassus W;
    W.build(rows, lcp.local_node, lcp.inverse);
    ActiveSetPgs active;
    const PgsResult result = active.solve(W, lcp.c, lcp.weight, rows, cap, 0, 8);  // tolerance 0
    CHECK(result.iterations <= cap);
    if (result.iterations < cap) CHECK(result.residual == 0);  // only an exact solution stops it sooner
    if (cap <= 10) CHECK(result.residual > 0);
    CHECK(result.residual == doctest::Approx(lcp_residual(W.matrix(), lcp.c, rows, &lcp.weight)).epsilon(1e-9));
    if (cap == 5) CHECK(active.rounds() == 0);
    if (cap >= 10) CHECK(active.rounds() >= 1);
  }
}

TEST_CASE("active-set PGS: the same multipliers on 1 and 2 threads") {
  std::mt19937 rng(25);
  const Lcp lcp = random_lcp(40, 220, 0.3, rng);  // W_AA's new columns split over tasks
  std::vector<double> lambda[2];
  for (const int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    RowTable rows = lcp.problem.rows;
    Delassus W;
    W.build(rows, lcp.local_node, lcp.inverse);
    ActiveSetPgs active;
    active.solve(W, lcp.c, lcp.weight, rows, 200000, 1e-10, 8);
    CHECK(active.rounds() >= 1);
    lambda[threads - 1] = rows.lambda;
  }
  CHECK(std::memcmp(lambda[0].data(), lambda[1].data(), sizeof(double) * lambda[0].size()) == 0);
}

namespace {

// Block as solve_pgs sees it without entry() and changed4(): one change at a time.
struct OneChangeAtATime {
  ActiveSetPgs::Block& block;
  double diagonal(int p) const { return block.diagonal(p); }
  void start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c) { block.start(lambda, c); }
  double w(int p) const { return block.w(p); }
  void changed(int p, double delta) { block.changed(p, delta); }
  void multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> out) const {
    block.multiply_rows(rows, x, out);
  }
};

// The deferred path is Block's alone, and the reference below does not take it.
static_assert(kDefersChanges<ActiveSetPgs::Block>);
static_assert(!kDefersChanges<OneChangeAtATime>);
static_assert(!kDefersChanges<Delassus>);
static_assert(!kDefersChanges<DenseLcpMatrix>);

}  // namespace

TEST_CASE("solve_pgs on W_AA: changes four at a time give the one-at-a-time sweep's multipliers bit for bit") {
  // A semi-definite W_AA (more rows than DOFs, as the flat finger's), its entries in slots
  // permuted against the positions, contacts with friction rows and unilateral rows.
  std::mt19937 rng(23);
  std::normal_distribution<double> normal;
  const int m = 45, dofs = 30;
  MatX J(m, dofs);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < dofs; ++j) J(i, j) = normal(rng);
  std::vector<int> slot(m);
  for (int p = 0; p < m; ++p) slot[p] = (7 * p + 3) % m;
  MatX W_by_slot(m, m);  // column slot[q], entry slot[p]: W_pq
  const MatX W = J * J.transpose();
  for (int p = 0; p < m; ++p)
    for (int q = 0; q < m; ++q) W_by_slot(slot[p], slot[q]) = W(p, q);
  PgsRows rows;
  VecX c(m), weight = VecX::Ones(m);
  for (int p = 0; p < m; ++p) {
    const bool friction = p % 3 != 0 && p < 30;  // rows 0, 3, .. 27 normals with two friction rows
    rows.normal_row.push_back(friction ? p - p % 3 : -1);
    rows.mu.push_back(friction ? 0.4 : 0.0);
    rows.lo.push_back(friction ? 0.0 : 0.0);
    rows.hi.push_back(friction ? 0.0 : 1e300);
    rows.lambda.push_back(0.0);
    c[p] = friction ? 3 * normal(rng) : normal(rng) - 0.5;
  }
  for (int subspace : {0, 8}) {
    CAPTURE(subspace);
    std::vector<double> w_blocked(m), w_single(m), product(m);
    PgsRows blocked_rows = rows, single_rows = rows;
    ActiveSetPgs::Block blocked(W_by_slot.data(), m, m, slot.data(), w_blocked.data(), product.data());
    ActiveSetPgs::Block single(W_by_slot.data(), m, m, slot.data(), w_single.data(), product.data());
    OneChangeAtATime one{single};
    // A loose tolerance first (sweeps that leave changes pending at a sweep's end), then tight.
    for (double tolerance : {1e-2, 1e-12}) {
      const PgsResult a = solve_pgs(blocked, c, weight, blocked_rows, 300, tolerance, subspace);
      const PgsResult b = solve_pgs(one, c, weight, single_rows, 300, tolerance, subspace);
      CHECK(a.iterations == b.iterations);
      CHECK(a.subspace_products == b.subspace_products);
      CHECK(std::memcmp(&a.residual, &b.residual, sizeof(double)) == 0);
      CHECK(std::memcmp(blocked_rows.lambda.data(), single_rows.lambda.data(), m * sizeof(double)) == 0);
      CHECK(std::memcmp(w_blocked.data(), w_single.data(), m * sizeof(double)) == 0);
    }
    int positive = 0;
    for (double l : blocked_rows.lambda) positive += l > 0;
    CHECK(positive >= 4);  // the deferred path ran: some sweeps changed four rows or more
  }
}
