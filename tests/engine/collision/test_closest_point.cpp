#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>

#include "engine/collision/closest_point.hpp"

using namespace sinew;

TEST_CASE("closest point on a triangle: matches a dense search of the triangle, with the right feature") {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 200;  // barycentric grid for the dense search: spacing ~1/200 of an edge
  int features[7] = {};
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p = 1.5 * Vec3(u(rng), u(rng), u(rng));
    const TriangleClosest r = closest_point_on_triangle(p, a, b, c);
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
        best = std::min(best, (q - p).norm());
      }
    const double found = (r.point - p).norm();
    // The grid point nearest the true closest point is within one grid diagonal of it.
    const double spacing = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / n;
    REQUIRE(found <= best + 1e-12);
    REQUIRE(found >= best - 2 * spacing);
    // Barycentric coordinates reproduce the point, are >= 0 and sum to one.
    REQUIRE((r.bary[0] * a + r.bary[1] * b + r.bary[2] * c - r.point).norm() < 1e-12);
    REQUIRE(r.bary.minCoeff() >= 0);
    REQUIRE(std::abs(r.bary.sum() - 1) < 1e-12);
    // The point lies on the reported feature.
    const Vec3 n_face = (b - a).cross(c - a).normalized();
    REQUIRE(std::abs((r.point - a).dot(n_face)) < 1e-12);
    auto on_segment = [&](const Vec3& s, const Vec3& e) {
      return ((r.point - s).cross(e - s)).norm() < 1e-9 * (e - s).norm();
    };
    switch (r.feature) {
      case TriangleFeature::A: REQUIRE((r.point - a).norm() == 0); break;
      case TriangleFeature::B: REQUIRE((r.point - b).norm() == 0); break;
      case TriangleFeature::C: REQUIRE((r.point - c).norm() == 0); break;
      case TriangleFeature::AB: REQUIRE(on_segment(a, b)); break;
      case TriangleFeature::BC: REQUIRE(on_segment(b, c)); break;
      case TriangleFeature::CA: REQUIRE(on_segment(c, a)); break;
      case TriangleFeature::Face: break;
    }
    ++features[static_cast<int>(r.feature)];
  }
  for (int f = 0; f < 7; ++f) CHECK(features[f] > 0);  // every region was exercised
}
