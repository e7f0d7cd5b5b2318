// Signed distance to a triangle mesh: sign from pseudo-normals against the analytic shape it
// approximates, gradient against central differences, Embree against brute force.
#include <doctest/doctest.h>

#include <random>

#include "engine/collision/mesh_sdf.hpp"
#include "engine/geometry/surface_mesher.hpp"

using namespace sinew;

namespace {

Shape capsule_shape() {
  Shape shape;
  Primitive p;
  p.kind = PrimitiveKind::Capsule;
  p.size = Vec3(0.3, 0.25, 0.3);
  shape.parts.push_back(p);
  return shape;
}

}  // namespace

TEST_CASE("mesh sdf: sign and value follow the shape the mesh approximates; Embree equals brute force") {
  const Shape shape = capsule_shape();
  const double resolution = 0.04;
  const MeshSdf sdf(mesh_shape_surface(shape, resolution));
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  double worst_value = 0;
  int inside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const SdfSample s = sdf.sdf(p), slow = sdf.sdf_brute_force(p);
    REQUIRE(s.phi == doctest::Approx(slow.phi).epsilon(1e-12));
    REQUIRE(std::abs(s.normal.norm() - 1) < 1e-9);
    const double exact = shape.sdf(p);
    // A chord of length l sags l^2 / (8 r) below a surface of radius r = 0.3 m; marching
    // tetrahedra's triangles span up to a cube diagonal, l = sqrt(3) resolution: 2 mm;
    // vertices interpolated linearly along the tetrahedra's edges add up to ~res^2 / (8 r),
    // 0.7 mm. 3 mm bounds both.
    worst_value = std::max(worst_value, std::abs(s.phi - exact));
    if (std::abs(exact) > 3e-3) REQUIRE((s.phi < 0) == (exact < 0));
    inside += exact < 0;
  }
  MESSAGE("worst |phi_mesh - phi_shape| " << worst_value << " m over 2000 points, " << inside << " inside");
  CHECK(worst_value < 3e-3);
  CHECK(inside > 100);
}

TEST_CASE("mesh sdf: the normal is the gradient of phi away from the surface (central differences)") {
  const MeshSdf sdf(mesh_shape_surface(capsule_shape(), 0.04));
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  double worst = 0;
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 150; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const SdfSample s = sdf.sdf(p);
    // phi of a mesh is only piecewise smooth (the nearest feature changes); outside, within
    // one nearest-feature region, it is |p - c| with curvature 1/|phi|. Inside, medial
    // kinks are everywhere near the axis: check outside points only, at 5 cm or more.
    if (s.phi < 0.05) continue;
    const double step = 1e-6;
    Vec3 g;
    for (int a = 0; a < 3; ++a) {
      const Vec3 d = step * Vec3::Unit(a);
      g[a] = (sdf.sdf(p + d).phi - sdf.sdf(p - d).phi) / (2 * step);
    }
    // Error step^2 / (6 phi^2) + rounding 1e-16 / step: ~1e-10, unless a feature boundary
    // lies within the step (then phi stays C1 and the error is still O(step / phi)).
    worst = std::max(worst, (g - s.normal).norm());
    ++checked;
  }
  MESSAGE(checked << " points, worst |fd - normal| " << worst);
  CHECK(checked >= 100);
  CHECK(worst < 1e-4);
}
