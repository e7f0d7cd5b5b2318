// Camera matrices and the default framing of a bounding box.
#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include "render/camera.hpp"

using namespace sinew;

namespace {

Aabb make_box(const Vec3& lo, const Vec3& hi) {
  Aabb b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

}  // namespace

TEST_CASE("camera: the view matrix puts the eye at the origin looking down -z") {
  Camera c;
  c.eye = {1, 2, 3};
  c.target = {1, 2, -5};
  const Eigen::Matrix4f v = c.view();
  const Eigen::Vector4f eye = v * Eigen::Vector4f(1, 2, 3, 1);
  CHECK(eye.head<3>().norm() == doctest::Approx(0).epsilon(1e-6));
  const Eigen::Vector4f ahead = v * Eigen::Vector4f(1, 2, 0, 1);
  CHECK(ahead.z() == doctest::Approx(-3));
  CHECK(ahead.x() == doctest::Approx(0));
}

TEST_CASE("camera: to_pixel puts the target in the image centre and +up towards the top") {
  Camera c;
  c.eye = {0, 0, 5};
  c.target = {0, 0, 0};
  const Eigen::Vector2f centre = c.to_pixel(Vec3::Zero(), 200, 100);
  CHECK(centre.x() == doctest::Approx(100));
  CHECK(centre.y() == doctest::Approx(50));
  CHECK(c.to_pixel(Vec3(0, 1, 0), 200, 100).y() < 50);
  CHECK(c.to_pixel(Vec3(1, 0, 0), 200, 100).x() > 100);
  bool in_front = true;
  c.to_pixel(Vec3(0, 0, 10), 200, 100, &in_front);
  CHECK(!in_front);
}

TEST_CASE("camera: frame_box keeps every corner of the box inside the image, for any orbit") {
  const Aabb box = make_box({-1, 0, -0.2}, {1, 0.5, 0.2});
  for (double orbit : {0.0, 30.0, 90.0, 200.0})
    for (double aspect : {16.0 / 9.0, 0.5}) {
      const Camera c = frame_box(box, Vec3::UnitY(), orbit, 20, 40, aspect);
      const int w = int(400 * aspect), h = 400;
      const Eigen::Vector2f centre = c.to_pixel(0.5 * (box.lo + box.hi), w, h);
      CHECK(centre.x() == doctest::Approx(w / 2.0));
      CHECK(centre.y() == doctest::Approx(h / 2.0));
      for (int k = 0; k < 8; ++k) {
        const Vec3 p((k & 1 ? box.hi : box.lo).x(), (k & 2 ? box.hi : box.lo).y(), (k & 4 ? box.hi : box.lo).z());
        bool in_front = false;
        const Eigen::Vector2f px = c.to_pixel(p, w, h, &in_front);
        CHECK(in_front);
        CHECK(px.x() >= 0);
        CHECK(px.x() <= w);
        CHECK(px.y() >= 0);
        CHECK(px.y() <= h);
        const float depth = (c.view() * Eigen::Vector4f(float(p.x()), float(p.y()), float(p.z()), 1)).z();
        CHECK(-depth > c.near);
        CHECK(-depth < c.far);
      }
    }
}

TEST_CASE("camera: orbit and elevation move the eye around the up axis") {
  const Aabb box = make_box({-1, -1, -1}, {1, 1, 1});
  const Camera front = frame_box(box, Vec3::UnitY(), 0, 0, 40, 1);
  CHECK(front.eye.x() == doctest::Approx(0).epsilon(1e-5));
  CHECK(front.eye.z() > 0);  // reference axis +z when up is y
  const Camera side = frame_box(box, Vec3::UnitY(), 90, 0, 40, 1);
  CHECK(side.eye.z() == doctest::Approx(0).epsilon(1e-5));
  CHECK(std::abs(side.eye.x()) == doctest::Approx(front.eye.z()));
  const Camera high = frame_box(box, Vec3::UnitY(), 0, 60, 40, 1);
  CHECK(high.eye.y() > 0.8 * high.eye.z());
  // z-up scenes orbit from +x.
  CHECK(orbit_reference(Vec3::UnitZ()).isApprox(Vec3::UnitX()));
}
