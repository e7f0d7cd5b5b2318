// add_scaled (engine/math/add_scaled.cpp): y += a x with one multiply and one add per entry,
// on either path (AVX2 where the CPU has it, and SSE2), so its bits equal the plain scalar
// loop's.
// A fused multiply-add rounds once and differs in the last bit for most of these inputs.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
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
