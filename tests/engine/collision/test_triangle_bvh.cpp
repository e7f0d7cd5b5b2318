// The Embree path against the brute-force path, before and after a refit.
#include <doctest/doctest.h>

#include <random>

#include "engine/collision/triangle_bvh.hpp"
#include "engine/geometry/surface_mesher.hpp"

using namespace sinew;

namespace {

TriMesh ellipsoid_mesh() {
  Shape shape;
  Primitive p;
  p.kind = PrimitiveKind::Ellipsoid;
  p.size = Vec3(0.5, 0.3, 0.4);
  shape.parts.push_back(p);
  return mesh_shape_surface(shape, 0.05);
}

void check_against_brute_force(const TriangleBvh& bvh, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const NearestTriangle fast = bvh.nearest(p), slow = bvh.nearest_brute_force(p);
    REQUIRE(fast.triangle >= 0);
    // Same distance (the triangle may differ only on exact ties).
    REQUIRE(std::abs(std::sqrt(fast.distance_sq) - std::sqrt(slow.distance_sq)) < 1e-12);
    const double limit = 0.1;  // bounded search: both find nothing or the same distance
    const NearestTriangle near_fast = bvh.nearest(p, limit), near_slow = bvh.nearest_brute_force(p, limit);
    REQUIRE((near_fast.triangle >= 0) == (near_slow.triangle >= 0));
  }
}

}  // namespace

TEST_CASE("triangle bvh: Embree nearest triangle equals the brute-force one, also after a refit") {
  const TriMesh mesh = ellipsoid_mesh();
  MESSAGE(mesh.triangles.size() << " triangles");
  std::mt19937 rng(9);
  TriangleBvh bvh(mesh.vertices, mesh.triangles, true);
  check_against_brute_force(bvh, rng);
  // Deform (twist and stretch) and refit: the BVH must follow the vertices.
  std::vector<Vec3> moved = mesh.vertices;
  for (Vec3& v : moved) v = Vec3(v.x() * 1.3 + 0.2, v.y() + 0.5 * v.x() * v.x(), v.z() - 0.3 * v.y());
  bvh.update(moved);
  check_against_brute_force(bvh, rng);
  CHECK((bvh.vertices()[7] - moved[7]).norm() == 0);
}
