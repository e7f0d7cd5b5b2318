#include <doctest/doctest.h>

#include <random>

#include "engine/constraints/lcp_pgs.hpp"

using namespace sinew;

namespace {

// A random SPD matrix with a dominant diagonal (PGS converges for any SPD W; the
// diagonal dominance just keeps the iteration count small for the test).
MatX random_spd(int m, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  MatX B(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) B(i, j) = normal(rng);
  return B * B.transpose() + m * MatX::Identity(m, m);
}

}  // namespace

TEST_CASE("PGS converges to an LCP solution: residual falls with the iterations") {
  std::mt19937 rng(7);
  const int m = 30;
  const MatX W = random_spd(m, rng);
  std::normal_distribution<double> normal;
  VecX c(m);
  for (int i = 0; i < m; ++i) c[i] = normal(rng);
  double previous = 1e300;
  for (int iterations : {1, 5, 20, 200}) {
    RowTable rows;
    for (int i = 0; i < m; ++i) rows.add_row(RowKind::Energy, 0, 0, 1e300, i);
    solve_pgs(W, c, rows, iterations, 0);
    const double residual = lcp_residual(W, c, rows);
    MESSAGE(iterations << " sweeps: LCP residual " << residual);
    CHECK(residual <= previous);
    previous = residual;
    for (double l : rows.lambda) CHECK(l >= 0);
  }
  CHECK(previous < 1e-10 * c.norm());
}

TEST_CASE("PGS: friction rows stay inside the Coulomb box of their normal row") {
  std::mt19937 rng(3);
  const int contacts = 6;
  const MatX W = random_spd(3 * contacts, rng);
  VecX c(3 * contacts);
  RowTable rows;
  for (int k = 0; k < contacts; ++k) {
    const int n = rows.add_row(RowKind::Contact, 0, 0, 1e300, 3 * k);
    c[n] = -1.0;  // approaching: needs a push
    for (int t = 0; t < 2; ++t) {
      const int r = rows.add_row(RowKind::Friction, 0, 0, 0, 3 * k + 1 + t);
      rows.normal_row[r] = n;
      rows.mu[r] = 0.3;
      c[r] = 5.0 * (t ? 1 : -1);  // strong sliding: friction saturates
    }
  }
  solve_pgs(W, c, rows, 500, 1e-12);
  for (int k = 0; k < contacts; ++k) {
    const double ln = rows.lambda[3 * k];
    CHECK(ln > 0);
    for (int t = 1; t <= 2; ++t) CHECK(std::abs(rows.lambda[3 * k + t]) <= 0.3 * ln * (1 + 1e-12));
  }
  CHECK(lcp_residual(W, c, rows) < 1e-8);
}

TEST_CASE("PGS warm start from the solution stops after one sweep") {
  std::mt19937 rng(11);
  const MatX W = random_spd(10, rng);
  const VecX c = -VecX::Ones(10);
  RowTable rows;
  for (int i = 0; i < 10; ++i) rows.add_row(RowKind::Energy, 0, 0, 1e300, i);
  solve_pgs(W, c, rows, 1000, 1e-14);
  CHECK(solve_pgs(W, c, rows, 1000, 1e-10).iterations == 1);
}
