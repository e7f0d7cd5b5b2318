#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "engine/geometry/shape.hpp"

using sinew::Mat3;
using sinew::Primitive;
using sinew::PrimitiveKind;
using sinew::Shape;
using sinew::Vec3;

namespace {

// All expected distances below are sums/roots of short decimals: 1e-12 covers rounding.
constexpr double kTol = 1e-12;

Primitive make(PrimitiveKind kind, const Vec3& size, const Vec3& center = Vec3::Zero(),
               const Mat3& rotation = Mat3::Identity()) {
  Primitive p;
  p.kind = kind;
  p.size = size;
  p.center = center;
  p.rotation = rotation;
  return p;
}

// Exact distance from an outside point y to the ellipsoid with semi-axes a: the nearest
// point is x_i = a_i^2 y_i / (t + a_i^2) where t > 0 solves sum (a_i y_i / (t + a_i^2))^2 = 1
// (the left side decreases in t, so bisection finds it).
double ellipsoid_distance_outside(Vec3 y, const Vec3& a) {
  y = y.cwiseAbs();
  auto g = [&](double t) {
    double s = 0;
    for (int i = 0; i < 3; ++i) s += std::pow(a[i] * y[i] / (t + a[i] * a[i]), 2);
    return s - 1;
  };
  double lo = 0, hi = 1;
  while (g(hi) > 0) hi *= 2;
  for (int it = 0; it < 200; ++it) (g(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double t = 0.5 * (lo + hi);
  Vec3 x;
  for (int i = 0; i < 3; ++i) x[i] = a[i] * a[i] * y[i] / (t + a[i] * a[i]);
  return (x - y).norm();
}

}  // namespace

TEST_CASE("shape: sphere distances") {
  const Primitive s = make(PrimitiveKind::Sphere, Vec3(0.5, 9, 9), Vec3(1, 2, 3));
  CHECK(s.sdf(Vec3(1, 2, 3)) == -0.5);
  CHECK(std::abs(s.sdf(Vec3(1, 2, 3.75)) - 0.25) < kTol);
  CHECK(std::abs(s.sdf(Vec3(1 + 0.3, 2 + 0.4, 3)) - 0.0) < kTol);  // |(0.3, 0.4)| = 0.5
  const auto b = s.bounds();
  CHECK((b.lo - Vec3(0.5, 1.5, 2.5)).norm() < kTol);
  CHECK((b.hi - Vec3(1.5, 2.5, 3.5)).norm() < kTol);
}

TEST_CASE("shape: box distances inside, at faces, edges and corners") {
  const Primitive b = make(PrimitiveKind::Box, Vec3(1, 2, 3));
  CHECK(std::abs(b.sdf(Vec3(1.3, 0, 0)) - 0.3) < kTol);            // face
  CHECK(std::abs(b.sdf(Vec3(1.3, 2.4, 0)) - 0.5) < kTol);          // edge: |(0.3, 0.4)|
  CHECK(std::abs(b.sdf(Vec3(-1.2, -2.3, 3.6)) - std::sqrt(0.04 + 0.09 + 0.36)) < kTol);  // corner
  CHECK(std::abs(b.sdf(Vec3(0.9, 0, 0)) + 0.1) < kTol);            // inside: nearest face x
  CHECK(std::abs(b.sdf(Vec3(0, 0, 0)) + 1.0) < kTol);
  CHECK(std::abs(b.sdf(Vec3(0.5, 1.8, -2.9)) + 0.1) < kTol);       // nearest face z
}

TEST_CASE("shape: capsule and cylinder distances") {
  const Primitive cap = make(PrimitiveKind::Capsule, Vec3(0.5, 1, 0));
  CHECK(std::abs(cap.sdf(Vec3(0, 1.7, 0)) - 0.2) < kTol);          // above the top cap
  CHECK(std::abs(cap.sdf(Vec3(0.8, 0.3, 0)) - 0.3) < kTol);        // beside the side
  CHECK(std::abs(cap.sdf(Vec3(0.3, -1.4, 0)) - 0.0) < kTol);       // on the bottom cap
  CHECK(std::abs(cap.sdf(Vec3(0, 0.2, 0)) + 0.5) < kTol);

  const Primitive cyl = make(PrimitiveKind::Cylinder, Vec3(0.5, 1, 0));
  CHECK(std::abs(cyl.sdf(Vec3(0.3, 1.4, 0.4)) - 0.4) < kTol);      // above the flat end, |xz| = r
  CHECK(std::abs(cyl.sdf(Vec3(0.8, 1.4, 0)) - 0.5) < kTol);        // off the rim: |(0.3, 0.4)|
  CHECK(std::abs(cyl.sdf(Vec3(0, 0.3, 0.9)) - 0.4) < kTol);        // beside the side
  CHECK(std::abs(cyl.sdf(Vec3(0, 0.95, 0)) + 0.05) < kTol);        // inside, near the end
  CHECK(std::abs(cyl.sdf(Vec3(0.4, 0, 0)) + 0.1) < kTol);          // inside, near the side
}

TEST_CASE("shape: rotation maps local to world") {
  // Rotating by -90 degrees about z sends local y to world +x: the cylinder lies along x.
  const Mat3 r = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  REQUIRE((r * Vec3::UnitY() - Vec3::UnitX()).norm() < kTol);
  const Vec3 c(1, 2, 3);
  const Primitive cyl = make(PrimitiveKind::Cylinder, Vec3(0.5, 1, 0), c, r);
  CHECK(std::abs(cyl.sdf(c + Vec3(1.4, 0, 0)) - 0.4) < kTol);
  CHECK(std::abs(cyl.sdf(c + Vec3(0, 0.8, 0)) - 0.3) < kTol);
  CHECK(std::abs(cyl.sdf(c + Vec3(0, 0, -0.7)) - 0.2) < kTol);
  const auto b = cyl.bounds();
  CHECK((b.lo - (c - Vec3(1, 0.5, 0.5))).norm() < kTol);
  CHECK((b.hi - (c + Vec3(1, 0.5, 0.5))).norm() < kTol);

  // An asymmetric turn (30 degrees about z): the tip of a capsule is at c + R (0, h + r, 0).
  const Mat3 r30 = Eigen::AngleAxisd(M_PI / 6, Vec3::UnitZ()).toRotationMatrix();
  const Primitive cap = make(PrimitiveKind::Capsule, Vec3(0.5, 1, 0), c, r30);
  CHECK(std::abs(cap.sdf(c + r30 * Vec3(0, 1.7, 0)) - 0.2) < kTol);
  CHECK(std::abs(cap.sdf(c + r30 * Vec3(0.9, -0.4, 0)) - 0.4) < kTol);

  // A box turned 45 degrees about z: its corner (1, 1, 0) goes to (0, sqrt 2, 0).
  const Mat3 r45 = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
  const Primitive box = make(PrimitiveKind::Box, Vec3(1, 1, 1), Vec3::Zero(), r45);
  CHECK(std::abs(box.sdf(Vec3(0, std::sqrt(2.0) + 0.25, 0)) - 0.25) < kTol);
  CHECK(std::abs(box.bounds().hi.x() - std::sqrt(2.0)) < kTol);
  CHECK(std::abs(box.bounds().hi.z() - 1.0) < kTol);
}

TEST_CASE("shape: ellipsoid sign is exact and distance is a close lower bound") {
  const Vec3 a(1.0, 0.4, 0.2);
  const Primitive e = make(PrimitiveKind::Ellipsoid, a);
  // On the axes the estimate is exact: k0 (k0 - 1) / k1 = d for p = (a_i + d) e_i.
  CHECK(std::abs(e.sdf(Vec3(1.3, 0, 0)) - 0.3) < kTol);
  CHECK(std::abs(e.sdf(Vec3(0, -0.5, 0)) - 0.1) < kTol);
  CHECK(e.sdf(Vec3::Zero()) < 0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 2000; ++n) {
    const Vec3 on = Vec3(u(rng), u(rng), u(rng)).normalized().cwiseProduct(a);  // on the surface
    CHECK(e.sdf(on * (1 - 1e-9)) < 0);
    CHECK(e.sdf(on * (1 + 1e-9)) > 0);
    // Anywhere outside: a lower bound of the distance (the voxelizer prunes with that).
    const Vec3 p = on * (1 + 0.5 * std::abs(u(rng)));
    CHECK(e.sdf(p) <= ellipsoid_distance_outside(p, a) * (1 + 1e-9));
    // Near the surface: first-order exact. At distance d along the normal (d below the
    // smallest curvature radius 0.2^2 / 1 = 0.04) the error is O(d^2 / 0.04), 2.5e-11 here.
    const double d = 1e-6;
    const Vec3 q = on + d * on.cwiseQuotient(a.cwiseProduct(a)).normalized();
    CHECK(std::abs(e.sdf(q) - d) < 1e-2 * d);
  }
  // Rotated ellipsoid bounds: the extent along world x of a = (1, 0.4, 0.2) turned 90
  // degrees about z is the old y semi-axis.
  const Mat3 r = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const Primitive er = make(PrimitiveKind::Ellipsoid, a, Vec3::Zero(), r);
  CHECK(std::abs(er.bounds().hi.x() - 0.4) < kTol);
  CHECK(std::abs(er.bounds().hi.y() - 1.0) < kTol);
  // Turned 45 degrees the bounds are tight: hi_x = sqrt((1 cos45)^2 + (0.4 sin45)^2).
  const Mat3 r45 = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
  const Primitive e45 = make(PrimitiveKind::Ellipsoid, a, Vec3::Zero(), r45);
  CHECK(std::abs(e45.bounds().hi.x() - std::sqrt(0.5 + 0.5 * 0.16)) < kTol);
  CHECK(std::abs(e45.bounds().hi.z() - 0.2) < kTol);
}

TEST_CASE("shape: union is the minimum and its bounds the union") {
  Shape s;
  s.parts.push_back(make(PrimitiveKind::Sphere, Vec3(0.5, 0, 0), Vec3(-1, 0, 0)));
  s.parts.push_back(make(PrimitiveKind::Box, Vec3(0.5, 0.5, 0.5), Vec3(1, 0, 0)));
  CHECK(std::abs(s.sdf(Vec3(-1, 0, 0)) + 0.5) < kTol);
  CHECK(std::abs(s.sdf(Vec3(1, 0, 0)) + 0.5) < kTol);
  CHECK(std::abs(s.sdf(Vec3(0, 0, 0)) - 0.5) < kTol);   // 0.5 from both
  CHECK(std::abs(s.sdf(Vec3(0.2, 0, 0)) - 0.3) < kTol);  // nearer the box
  const auto b = s.bounds();
  CHECK((b.lo - Vec3(-1.5, -0.5, -0.5)).norm() < kTol);
  CHECK((b.hi - Vec3(1.5, 0.5, 0.5)).norm() < kTol);
  CHECK(Shape{}.bounds().empty());
}

TEST_CASE("shape: primitive kind names round-trip") {
  for (PrimitiveKind k : {PrimitiveKind::Box, PrimitiveKind::Sphere, PrimitiveKind::Cylinder,
                          PrimitiveKind::Capsule, PrimitiveKind::Ellipsoid}) {
    bool ok = false;
    CHECK(sinew::parse_primitive_kind(sinew::primitive_kind_name(k), ok) == k);
    CHECK(ok);
  }
  bool ok = true;
  sinew::parse_primitive_kind("cone", ok);
  CHECK_FALSE(ok);
}
