// add_scaled (engine/math/add_scaled.cpp): y += a x with one multiply and one add per entry,
// on either path (AVX2 where the CPU has it, and SSE2), so its bits equal the plain scalar
// loop's.
// A fused multiply-add rounds once and differs in the last bit for most of these inputs.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <optional>
#include <random>
#include <vector>

#include "engine/core/cpu_features.hpp"
#include "engine/math/add_scaled.hpp"

using namespace sinew;

TEST_CASE("add_scaled: the same bits as y[i] + x[i] * a, for every length and alignment") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  int fused_would_differ = 0;
  if (!use_avx2()) WARN_MESSAGE(false, "this CPU has no AVX2: both passes below take the SSE2 path");
  for (const bool avx2 : {true, false}) {
    for (int n = 0; n <= 37; ++n)
      for (int offset = 0; offset < 4; ++offset) {  // unaligned starts too
        std::vector<double> x(n + offset), y(n + offset), expected;
        for (double& v : x) v = value(rng);
        for (double& v : y) v = value(rng);
        const double a = value(rng) * 1e3;
        expected = y;
        for (int i = offset; i < n + offset; ++i) {
          volatile double product = x[i] * a;  // rounded on its own, then added
          expected[i] = y[i] + product;
          fused_would_differ += std::fma(x[i], a, y[i]) != expected[i];
        }
        if (avx2) {
          add_scaled(y.data() + offset, x.data() + offset, a, n);
        } else {
          const BaselineKernelsOnly baseline;
          REQUIRE_FALSE(use_avx2());
          add_scaled(y.data() + offset, x.data() + offset, a, n);
        }
        CAPTURE(avx2);
        CAPTURE(n);
        CAPTURE(offset);
        CHECK((y.empty() || std::memcmp(y.data(), expected.data(), sizeof(double) * y.size()) == 0));  // no null to memcmp
      }
  }
  // The check above could tell a fused path from this one.
  CHECK(fused_would_differ > 200);
}

TEST_CASE("add_scaled3 and set_scaled3: the bits of y[i] + ((x0[i] a0 + x1[i] a1) + x2[i] a2) and of the sum alone, on both paths") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  int fused_would_differ = 0;
  for (const bool avx2 : {true, false}) {
    for (int n = 0; n <= 37; ++n)
      for (int offset = 0; offset < 4; ++offset) {
        std::vector<double> x0(n + offset), x1(n + offset), x2(n + offset), y(n + offset), expected;
        for (auto* v : {&x0, &x1, &x2, &y})
          for (double& e : *v) e = value(rng);
        const double a0 = value(rng) * 1e3, a1 = value(rng) * 1e3, a2 = value(rng) * 1e3;
        expected = y;
        for (int i = offset; i < n + offset; ++i) {
          volatile double p0 = x0[i] * a0, p1 = x1[i] * a1, p2 = x2[i] * a2;  // each rounded on its own
          volatile double sum = p0 + p1;
          expected[i] = y[i] + (sum + p2);
          fused_would_differ += std::fma(x2[i], a2, std::fma(x1[i], a1, x0[i] * a0)) + y[i] != expected[i];
        }
        std::vector<double> set = y, set_expected = y;  // set_scaled3: the sum alone, y unread
        for (int i = offset; i < n + offset; ++i) {
          volatile double p0 = x0[i] * a0, p1 = x1[i] * a1, p2 = x2[i] * a2;
          volatile double sum = p0 + p1;
          set_expected[i] = sum + p2;
        }
        const auto run = [&] {
          add_scaled3(y.data() + offset, x0.data() + offset, x1.data() + offset, x2.data() + offset, a0, a1, a2, n);
          set_scaled3(set.data() + offset, x0.data() + offset, x1.data() + offset, x2.data() + offset, a0, a1, a2, n);
        };
        if (avx2) {
          run();
        } else {
          const BaselineKernelsOnly baseline;
          REQUIRE_FALSE(use_avx2());
          run();
        }
        CAPTURE(avx2);
        CAPTURE(n);
        CAPTURE(offset);
        CHECK((y.empty() || std::memcmp(y.data(), expected.data(), sizeof(double) * y.size()) == 0));
        CHECK((set.empty() || std::memcmp(set.data(), set_expected.data(), sizeof(double) * set.size()) == 0));
      }
  }
  // The check above could tell a contracted path from this one: of the 2 x 38 x 4 x ~20
  // entries compared, at least one in twenty would differ.
  MESSAGE(fused_would_differ << " entries would differ fused");
  CHECK(fused_would_differ > 300);
}

TEST_CASE("add_scaled4 and add_scaled_nonzero: the bits of add_scaled on each column in turn, on both paths") {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (const bool avx2 : {true, false}) {
    std::optional<BaselineKernelsOnly> baseline;
    if (!avx2) baseline.emplace();
    for (int n = 0; n <= 23; ++n) {
      CAPTURE(avx2);
      CAPTURE(n);
      // 11 columns, some with a zero scale (left out), so that a last partial group remains.
      std::vector<std::vector<double>> x(11, std::vector<double>(n));
      std::vector<double> a(11), y(n);
      for (auto& column : x)
        for (double& v : column) v = value(rng);
      for (double& v : y) v = value(rng);
      for (int k = 0; k < 11; ++k) a[k] = k % 4 == 1 || k == 10 ? 0.0 : value(rng) * 1e3;  // 7 non-zero
      std::vector<double> expected = y, got = y, four = y;
      for (int k = 0; k < 11; ++k)
        if (a[k] != 0) add_scaled(expected.data(), x[k].data(), a[k], n);
      add_scaled_nonzero(got.data(), n, 11, a.data(), [&](int k) { return x[k].data(); });
      CHECK((n == 0 || std::memcmp(got.data(), expected.data(), sizeof(double) * n) == 0));
      // add_scaled4 alone on the first four columns.
      std::vector<double> one_by_one = y;
      const double* columns[4] = {x[0].data(), x[1].data(), x[2].data(), x[3].data()};
      for (int k = 0; k < 4; ++k) add_scaled(one_by_one.data(), columns[k], a[k], n);
      add_scaled4(four.data(), columns, a.data(), n);
      CHECK((n == 0 || std::memcmp(four.data(), one_by_one.data(), sizeof(double) * n) == 0));
    }
  }
}
