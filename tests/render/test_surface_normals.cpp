// Smooth per-vertex normals.
#include <doctest/doctest.h>

#include "render/surface_normals.hpp"

using namespace sinew;

TEST_CASE("normals: a flat counter-clockwise patch gets the plane's normal everywhere") {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Eigen::Vector3f> n;
  smooth_normals(v, {{0, 1, 2}, {0, 2, 3}}, n);
  REQUIRE(n.size() == 4);
  for (const auto& normal : n) CHECK(normal.isApprox(Eigen::Vector3f(0, 0, 1)));
}

TEST_CASE("normals: a closed tetrahedron's vertex normals point away from its centre") {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::array<int, 3>> t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::vector<Eigen::Vector3f> n;
  smooth_normals(v, t, n);
  const Vec3 centre(0.25, 0.25, 0.25);
  for (size_t i = 0; i < v.size(); ++i) {
    CHECK(n[i].norm() == doctest::Approx(1));
    CHECK(n[i].cast<double>().dot(v[i] - centre) > 0);
  }
  // The corner at the origin sees three equal faces: its normal is the diagonal.
  CHECK(n[0].isApprox(-Eigen::Vector3f(1, 1, 1).normalized()));
}

TEST_CASE("normals: larger triangles weigh more; unused vertices get zero") {
  // Vertex 0 shared by a big triangle facing +z and a small one facing +x.
  const std::vector<Vec3> v = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 0.1}, {0, 0.1, 0}, {5, 5, 5}};
  std::vector<Eigen::Vector3f> n;
  smooth_normals(v, {{0, 1, 2}, {0, 4, 3}}, n);
  CHECK(n[0].z() > 0.99f);
  CHECK(n[0].x() > 0);
  CHECK(n[5].isZero());
}
