// WideSupernodePasses (engine/solve/wide_supernode_passes.hpp): a wide supernode's forward and
// backward passes split into tasks give tree_forward's and tree_backward's bits on 1 and 2
// threads, in double and single precision, on AVX2 and baseline kernels; and the passes
// solve the supernode's triangle (the blocked backward order is still L^T's solve).
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "engine/core/cpu_features.hpp"
#include "engine/solve/tree_kernels.hpp"
#include "engine/solve/wide_supernode_passes.hpp"

using namespace sinew;

namespace wide_passes_test {

// A supernode of `columns` columns and `below` rows under its triangle, column-major, with
// the triangle's upper part left as garbage (as CHOLMOD leaves it: never read), in a vector
// y of `columns + below + 5` unknowns: the triangle's rows 3.., the rows below scattered
// after them in reverse order (a gather that is not a copy).
template <class Real>
struct Supernode {
  int columns, height;
  std::vector<Real> values;
  std::vector<int> rows;
  Supernode(int columns_, int below, unsigned seed) : columns(columns_), height(columns_ + below) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    values.resize(static_cast<size_t>(columns) * height);
    for (int k = 0; k < columns; ++k)
      for (int r = 0; r < height; ++r)
        // A well-conditioned lower triangle: unit-size diagonal, small entries below it.
        values[static_cast<size_t>(k) * height + r] =
            static_cast<Real>(r == k ? 1.5 + 0.5 * u(rng) : (r < k ? 1e30 : 0.1 * u(rng)));
    for (int r = 0; r < columns; ++r) rows.push_back(3 + r);
    for (int i = 0; i < below; ++i) rows.push_back(3 + columns + below - 1 - i);
  }
  BasicSupernodeView<Real> view() const { return {3, columns, height, values.data(), rows.data()}; }
  int unknowns() const { return height + 5; }
  double entry(int r, int k) const { return static_cast<double>(values[static_cast<size_t>(k) * height + r]); }
};

std::vector<double> random_values(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> y(n);
  for (double& v : y) v = u(rng);
  return y;
}

// y after the forward then the backward pass: by the serial kernels, or by `wide`'s tasks on
// the threads the caller allows; `threads` gets how many ran tasks in either pass.
template <class Real>
std::vector<double> both_passes(const Supernode<Real>& s, const std::vector<double>& start, WideSupernodePasses* wide,
                                int* threads = nullptr) {
  std::vector<double> y = start, gather(s.height);
  if (wide) {
    wide->forward(s.view(), y.data(), gather.data());
    if (threads) *threads = wide->last_pass_threads();
    wide->backward(s.view(), y.data(), gather.data());
    if (threads) *threads = std::max(*threads, wide->last_pass_threads());
  } else {
    tree_forward(s.view(), y.data(), gather.data());
    tree_backward(s.view(), y.data(), gather.data());
  }
  return y;
}

template <class Real>
void check_same_bits(int columns, int below) {
  CAPTURE(columns);
  CAPTURE(below);
  const Supernode<Real> s(columns, below, 7u + columns + below);
  const std::vector<double> start = random_values(s.unknowns(), 3);
  const std::vector<double> serial = both_passes(s, start, nullptr);
  WideSupernodePasses wide;
  wide.reserve(s.columns);
  for (const int threads : {1, 2}) {
    CAPTURE(threads);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    // Until both threads have run tasks of one pass (the second may join late, or not at
    // all in a call, on a loaded machine: then the caller runs every task), each run's bits
    // checked; at most 2000 runs.
    int most_threads = 0;
    for (int run = 0; run < 2000 && most_threads < threads; ++run) {
      int ran = 0;
      const std::vector<double> split = both_passes(s, start, &wide, &ran);
      most_threads = std::max(most_threads, ran);
      REQUIRE(std::memcmp(split.data(), serial.data(), sizeof(double) * serial.size()) == 0);
    }
    CHECK(most_threads == threads);
  }
}

}  // namespace wide_passes_test

using namespace wide_passes_test;

TEST_CASE("wide supernode passes: the bits of the serial passes on 1 and 2 threads") {
  REQUIRE(WideSupernodePasses::worth_two_threads(4 * kTreeBlock));
  REQUIRE_FALSE(WideSupernodePasses::worth_two_threads(4 * kTreeBlock - 1));
  // Whole and partial last blocks, odd half-blocks of rows, no rows below the triangle (a
  // root) and many (an inner separator).
  for (const int columns : {4 * kTreeBlock, 5 * kTreeBlock + 37, 9 * kTreeBlock + 3}) {
    for (const int below : {0, 1, 301}) {
      check_same_bits<double>(columns, below);
      check_same_bits<float>(columns, below);
    }
  }
}

TEST_CASE("wide supernode passes: AVX2 and baseline kernels give the same bits") {
  if (!use_avx2()) MESSAGE("this CPU has no AVX2: both runs take the baseline kernels");
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  const auto compare = [](const auto& s) {
    const std::vector<double> start = random_values(s.unknowns(), 4);
    WideSupernodePasses wide;
    wide.reserve(s.columns);
    const std::vector<double> vector = both_passes(s, start, &wide);
    const BaselineKernelsOnly scalar_only;
    const std::vector<double> scalar = both_passes(s, start, &wide);
    CHECK(std::memcmp(vector.data(), scalar.data(), sizeof(double) * vector.size()) == 0);
  };
  compare(Supernode<float>(5 * kTreeBlock + 37, 301, 11));
  compare(Supernode<double>(5 * kTreeBlock + 37, 301, 13));
}

TEST_CASE("wide supernode passes: the forward pass solves L y = b, the backward pass L^T z = y") {
  // The supernode's rows are a (columns + below) x columns block [T; B] of L. Forward: the
  // triangle's unknowns become y = T^-1 b and the rows below b_B - B y. Backward (from
  // values z_B below): the triangle's unknowns become z = T^-T (y - B^T z_B).
  const Supernode<double> s(5 * kTreeBlock + 37, 301, 12);
  const std::vector<double> b = random_values(s.unknowns(), 5);
  std::vector<double> y = b, gather(s.height);
  WideSupernodePasses wide;
  wide.reserve(s.columns);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  wide.forward(s.view(), y.data(), gather.data());
  // Both passes are backward stable: each row's residual is within gamma_n = n u (u = 2^-53,
  // n <= 700 terms: 7.8e-14) of the sum of its terms' magnitudes; 1e-12 leaves room.
  double worst = 0;
  for (int r = 0; r < s.height; ++r) {
    const int row = s.rows[r];
    double lhs = r < s.columns ? 0.0 : y[row], magnitude = std::abs(b[row]);  // below: b_B - B y + B y = b_B
    for (int k = 0; k <= std::min(r, s.columns - 1); ++k) {
      lhs += s.entry(r, k) * y[s.rows[k]];
      magnitude += std::abs(s.entry(r, k) * y[s.rows[k]]);
    }
    worst = std::max(worst, std::abs(lhs - b[row]) / magnitude);
  }
  CHECK(worst <= 1e-12);
  const std::vector<double> before = y;
  wide.backward(s.view(), y.data(), gather.data());
  worst = 0;
  for (int k = 0; k < s.columns; ++k) {  // T^T z + B^T z_B = y
    double lhs = 0, magnitude = std::abs(before[s.rows[k]]);
    for (int r = k; r < s.height; ++r) {
      lhs += s.entry(r, k) * y[s.rows[r]];
      magnitude += std::abs(s.entry(r, k) * y[s.rows[r]]);
    }
    worst = std::max(worst, std::abs(lhs - before[s.rows[k]]) / magnitude);
  }
  CHECK(worst <= 1e-12);
  for (int r = s.columns; r < s.height; ++r) CHECK(y[s.rows[r]] == before[s.rows[r]]);  // read, not written
}
