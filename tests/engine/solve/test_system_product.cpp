// multiply_system (engine/solve/system_product.hpp): A x for a symmetric A stored whole, as
// column dot products, equals Eigen's product and is bit-identical on 1 and 2 threads,
// below and above the size where it goes parallel; multiply_diagonal gives its bits for a
// matrix whose entries off the diagonal are zeros; multiply_node_blocked gives them for a
// matrix with the system pattern's node blocks, and refuses others.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>

#include "engine/assembly/system_pattern.hpp"
#include "engine/solve/system_product.hpp"
#include "tests/support/grid_matrices.hpp"

using namespace sinew;

namespace {

// A random symmetric matrix with `per_column` off-diagonal pairs per column.
SparseMatrix random_symmetric(int n, int per_column, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> row(0, n - 1);
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < n; ++j) {
    entries.emplace_back(j, j, 10 + u(rng));
    for (int k = 0; k < per_column; ++k) {
      const int i = row(rng);
      const double v = u(rng);
      entries.emplace_back(i, j, v), entries.emplace_back(j, i, v);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

}  // namespace

TEST_CASE("system product: Eigen's A x, the same bits on 1 and 2 threads") {
  // 300 x 300 with ~3k entries (serial) and 20,000 x 20,000 with ~420k (parallel).
  for (const auto& [n, per_column] : {std::pair{300, 5}, std::pair{20000, 10}}) {
    CAPTURE(n);
    const SparseMatrix A = random_symmetric(n, per_column, 3);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    VecX x(n);
    for (int i = 0; i < n; ++i) x[i] = u(rng);
    const VecX expected = A * x;
    const auto product = [&](int threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      VecX out;  // sized by the call
      multiply_system(A, x, out);
      return out;
    };
    const VecX one = product(1), two = product(2);
    REQUIRE(one.size() == n);
    CHECK((one - expected).norm() <= 1e-14 * expected.norm());
    CHECK(std::memcmp(one.data(), two.data(), sizeof(double) * n) == 0);
  }
}

TEST_CASE("system product: an uncompressed matrix gives the same product") {
  SparseMatrix A = random_symmetric(200, 4, 7);
  A.reserve(Eigen::VectorXi::Constant(200, 30));  // leaves room in every column: uncompressed
  REQUIRE_FALSE(A.isCompressed());
  const VecX x = VecX::LinSpaced(200, -1, 1);
  VecX out;
  multiply_system(A, x, out);
  CHECK((out - A * x).norm() <= 1e-14 * (A * x).norm());
}

// A diagonal matrix stored on a whole symmetric pattern (explicit zeros off the diagonal; a
// hyperelastic scene's mass matrix, whose other values assemble_system_matrix leaves stale
// and solve_newton never reads): multiply_diagonal gives
// multiply_system's bits, on x with zeros of both signs, subnormals and values of every scale.
TEST_CASE("system product: a diagonal matrix's product from its diagonal, bit for bit") {
  const int n = 600;
  SparseMatrix A = random_symmetric(n, 6, 11);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX d(n);
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) {
      if (it.row() == it.col()) d[k] = it.valueRef() = std::ldexp(1 + u(rng), static_cast<int>(20 * u(rng)));
      else it.valueRef() = 0.0;
    }
  VecX x(n);
  for (int i = 0; i < n; ++i) x[i] = std::ldexp(u(rng), static_cast<int>(40 * u(rng)));
  x[0] = -0.0, x[1] = 0.0, x[2] = -std::numeric_limits<double>::denorm_min(), x[3] = 1e-310;
  VecX general, diagonal;
  multiply_system(A, x, general);
  multiply_diagonal(d, x, diagonal);
  REQUIRE(diagonal.size() == n);
  CHECK(std::memcmp(general.data(), diagonal.data(), sizeof(double) * n) == 0);
  CHECK_FALSE(std::signbit(diagonal[0]));  // -0 * d: the column sum's +0
}

namespace {

// The node-blocked grid operator with random values on its pattern (symmetry is not needed
// for a product's bits).
SparseMatrix random_node_blocked(int nx, unsigned seed) {
  SparseMatrix A = test::node_blocked_grid_laplacian(nx);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < A.nonZeros(); ++k) A.valuePtr()[k] = std::ldexp(u(rng), static_cast<int>(8 * u(rng)));
  return A;
}

}  // namespace

TEST_CASE("node-blocked product: multiply_system's bits, on 1 and 2 threads, serial and parallel sizes") {
  // 5^3 points (375 unknowns, 6,525 entries: serial) and 20^3 (24,000 unknowns, 482,400: parallel).
  for (const int nx : {5, 20}) {
    CAPTURE(nx);
    const SparseMatrix A = random_node_blocked(nx, 21);
    REQUIRE(has_node_blocks(A));
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> u(-1, 1);
    VecX x(A.cols());
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = u(rng);
    x[0] = -0.0;
    VecX general;
    multiply_system(A, x, general);
    for (const int threads : {1, 2}) {
      CAPTURE(threads);
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      VecX blocked;
      multiply_node_blocked(A, x, blocked);
      REQUIRE(blocked.size() == A.rows());
      CHECK(std::memcmp(general.data(), blocked.data(), sizeof(double) * general.size()) == 0);
    }
  }
}

TEST_CASE("node-blocked product: the system pattern has node blocks, other matrices are refused") {
  // Two tets sharing a face, node 4 fixed: the pattern leaves its rows and columns out.
  const std::vector<std::array<int, 8>> tets = {{0, 1, 2, 3, -1, -1, -1, -1}, {1, 2, 3, 4, -1, -1, -1, -1}};
  const std::vector<int> free_index = {0, 1, 2, 3, -1};
  const SystemPattern pattern = build_system_pattern(tets, free_index, 4);
  CHECK(has_node_blocks(pattern.matrix));
  VecX x = VecX::LinSpaced(12, -1, 1), out;
  CHECK_NOTHROW(multiply_node_blocked(pattern.matrix, x, out));

  // A scalar matrix: columns of one node differ in length (the cheap test refuses it).
  const SparseMatrix scalar = random_symmetric(300, 5, 3);
  CHECK_FALSE(has_node_blocks(scalar));
  VecX y = VecX::Ones(300);
  CHECK_THROWS_AS(multiply_node_blocked(scalar, y, out), std::invalid_argument);

  // Equal column lengths but rows out of step (the second column of node 0 holds row 3 where
  // the first holds row 0): only the full test sees it.
  SparseMatrix shifted = test::node_blocked_grid_laplacian(2);
  REQUIRE(has_node_blocks(shifted));
  shifted.innerIndexPtr()[shifted.outerIndexPtr()[1]] = 3;
  CHECK_FALSE(has_node_blocks(shifted));
}
