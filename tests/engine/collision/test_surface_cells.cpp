#include <doctest/doctest.h>

#include <random>

#include "engine/collision/surface_cells.hpp"

using namespace sinew;

TEST_CASE("surface cells: vertices grouped by cell in ascending order, spread from the weights") {
  Embedding emb;
  emb.cell = {2, 0, 2, 1, 0};
  const std::array<double, 8> inside{0.125, 0.125, 0.125, 0.125, 0.125, 0.125, 0.125, 0.125};
  // Extrapolated: sum 1, sum |w| = 1.6 -> spread 0.3.
  const std::array<double, 8> outside{0.5, 0.5, 0.3, -0.3, 0, 0, 0, 0};
  emb.weights = {inside, inside, outside, inside, inside};
  const SurfaceCells sc = group_surface_by_cell(emb, 4);
  CHECK(sc.begin == std::vector<int>{0, 2, 3, 5, 5});
  CHECK(sc.vertices == std::vector<int>{1, 4, 3, 0, 2});
  CHECK(sc.spread[0] == 0);
  CHECK(sc.spread[2] == doctest::Approx(0.3));
  CHECK(sc.max_spread == doctest::Approx(0.3));
}

TEST_CASE("surface cells: a point with weights of spread s lies in the node box grown by s") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    std::array<Vec3, 8> x;
    Aabb box;
    for (Vec3& p : x) box.extend(p = Vec3(u(rng), u(rng), u(rng)));
    std::array<double, 8> w;
    double sum = 0, abs_sum = 0;
    for (double& wi : w) sum += wi = u(rng) + 0.4;
    for (double& wi : w) abs_sum += std::abs(wi /= sum);
    Vec3 p = Vec3::Zero();
    for (int n = 0; n < 8; ++n) p += w[n] * x[n];
    const Aabb grown = grow_by_spread(box, 0.5 * (abs_sum - 1));
    REQUIRE(((p.array() >= grown.lo.array() - 1e-12) && (p.array() <= grown.hi.array() + 1e-12)).all());
  }
}
