// Signed distances of the analytic obstacles: known values, unit normals, the normal
// against central differences of phi with a shrinking step, and the broad-phase bound.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>

#include "engine/collision/obstacle_sdf.hpp"

using namespace sinew;

namespace {

Mat3 some_rotation() { return Eigen::AngleAxisd(0.8, Vec3(0.2, 1, -0.5).normalized()).toRotationMatrix(); }

ObstacleDesc make(ObstacleDesc::Kind kind) {
  ObstacleDesc ob;
  ob.kind = kind;
  ob.normal = Vec3(0.3, 1, -0.2).normalized();
  ob.half_extents = Vec3(0.3, 0.2, 0.5);
  ob.radius = 0.25;
  ob.half_length = 0.4;
  ob.rotation = some_rotation();
  return ob;
}

// Distance from p to the nearest kink of phi (where its gradient jumps: inside the box where
// two faces are equally near), or a tenth of the curvature radius (off the box's edges,
// around the sphere's centre and the capsule's axis). Central differences are only checked away from them.
double distance_to_kink(const ObstacleDesc& ob, const Vec3& origin, const Vec3& p) {
  const Vec3 q = ob.rotation.transpose() * (p - origin);
  switch (ob.kind) {
    case ObstacleDesc::Kind::Box: {
      const Vec3 d = q.cwiseAbs() - ob.half_extents;
      // Outside, phi = |max(d, 0)| curves with radius |max(d, 0)| off an edge or corner
      // (two or more d_i > 0) and is flat off a face.
      if ((d.array() > 0).count() >= 2) return d.cwiseMax(0.0).norm() / 10;
      if ((d.array() > 0).any()) return 1;
      Vec3 sorted = d;
      std::sort(sorted.data(), sorted.data() + 3);
      return (sorted[2] - sorted[1]) / 2;
    }
    // Curvature radius: the distance to the centre / axis.
    case ObstacleDesc::Kind::Sphere: return (p - origin).norm() / 10;
    case ObstacleDesc::Kind::Capsule: return Vec3(q.x(), 0, q.z()).norm() / 10;
    default: return 1;
  }
}

const ObstacleDesc::Kind kKinds[] = {ObstacleDesc::Kind::Plane, ObstacleDesc::Kind::Box,
                                     ObstacleDesc::Kind::Sphere, ObstacleDesc::Kind::Capsule};
const char* kNames[] = {"plane", "box", "sphere", "capsule"};

}  // namespace

TEST_CASE("obstacle sdf: known values") {
  const Mat3 I = Mat3::Identity();
  CHECK(plane_sdf(Vec3(0, 1, 0), Vec3::UnitY(), Vec3(5, 3, -2)).phi == 2);
  CHECK(sphere_sdf(Vec3(1, 0, 0), 0.5, Vec3(1, 2, 0)).phi == 1.5);
  CHECK((sphere_sdf(Vec3(1, 0, 0), 0.5, Vec3(1, 2, 0)).normal - Vec3::UnitY()).norm() == 0);
  const Vec3 e(1, 2, 3);
  CHECK(box_sdf(Vec3::Zero(), I, e, Vec3(0.5, 0, 0)).phi == -0.5);                   // nearest face x
  CHECK((box_sdf(Vec3::Zero(), I, e, Vec3(-0.5, 0, 0)).normal - Vec3(-1, 0, 0)).norm() == 0);
  CHECK(box_sdf(Vec3::Zero(), I, e, Vec3(0, 0, 3.5)).phi == 0.5);                    // off a face
  CHECK(box_sdf(Vec3::Zero(), I, e, Vec3(4, 6, 3)).phi == doctest::Approx(5));        // off an edge: 3-4-5
  CHECK(box_sdf(Vec3::Zero(), I, e, Vec3(2, 3, 4)).phi == doctest::Approx(std::sqrt(3.0)));  // off a corner
  CHECK(capsule_sdf(Vec3::Zero(), I, 1, 0.5, Vec3(2, 0.3, 0)).phi == 1.5);            // beside the segment
  CHECK(capsule_sdf(Vec3::Zero(), I, 1, 0.5, Vec3(0, 3, 0)).phi == 1.5);              // beyond a cap
  CHECK(capsule_sdf(Vec3::Zero(), I, 1, 0.5, Vec3(0.1, 0, 0)).phi == doctest::Approx(-0.4));
}

TEST_CASE("obstacle sdf: the normal is the gradient of phi (central differences, shrinking step)") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  const Vec3 origin(0.1, -0.2, 0.3);
  for (int k = 0; k < 4; ++k) {
    const ObstacleDesc ob = make(kKinds[k]);
    int checked = 0, inside = 0;
    double worst_coarse = 0, worst_fine = 0;
    for (int trial = 0; trial < 400; ++trial) {
      // A third of the points within 0.6 m, a third within 0.3 m: many fall inside.
      const Vec3 p = origin + (trial % 3 == 0 ? 1.0 : trial % 3 == 1 ? 0.5 : 0.25) * Vec3(u(rng), u(rng), u(rng));
      if (distance_to_kink(ob, origin, p) < 1e-2) continue;
      const SdfSample s = obstacle_sdf(ob, origin, p);
      inside += s.phi < 0;
      REQUIRE(std::abs(s.normal.norm() - 1) < 1e-12);
      // Central differences: error step^2 |phi'''| / 6 plus rounding ~eps / step; a 10x
      // smaller step must cut the error about 100x.
      auto fd = [&](double step) {
        Vec3 g;
        for (int a = 0; a < 3; ++a) {
          const Vec3 d = step * Vec3::Unit(a);
          g[a] = (obstacle_sdf(ob, origin, p + d).phi - obstacle_sdf(ob, origin, p - d).phi) / (2 * step);
        }
        return (g - s.normal).norm();
      };
      worst_coarse = std::max(worst_coarse, fd(1e-3));
      worst_fine = std::max(worst_fine, fd(1e-4));
      ++checked;
    }
    MESSAGE(std::string(kNames[k]) << ": " << checked << " points (" << inside << " inside), worst |fd - normal| " << worst_coarse << " (step 1e-3), "
                      << worst_fine << " (step 1e-4)");
    CHECK(checked > 300);
    CHECK(inside > 20);
    // Curvature radii r >= 0.1 m at the kept points:
    // |phi'''| <~ 1 / r^2 <= 100, so step 1e-3 gives at most ~100e-6 / 6 ~ 2e-5.
    CHECK(worst_coarse < 1e-4);
    CHECK(worst_fine < 1e-6 + worst_coarse / 50);
  }
}

TEST_CASE("obstacle sdf: the broad-phase bound never exceeds phi inside the box it bounds") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5), size(0.01, 0.4), t(0, 1);
  const Vec3 origin(0.1, -0.2, 0.3);
  for (int k = 0; k < 4; ++k) {
    const ObstacleDesc ob = make(kKinds[k]);
    int tight = 0;
    for (int trial = 0; trial < 300; ++trial) {
      Aabb box;
      const Vec3 c = origin + Vec3(u(rng), u(rng), u(rng));
      const Vec3 half(size(rng), size(rng), size(rng));
      box.extend(c - half);
      box.extend(c + half);
      const double bound = obstacle_distance_bound(ob, origin, box);
      double lowest = 1e300;
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p(corner & 1 ? box.hi.x() : box.lo.x(), corner & 2 ? box.hi.y() : box.lo.y(),
                     corner & 4 ? box.hi.z() : box.lo.z());
        lowest = std::min(lowest, obstacle_sdf(ob, origin, p).phi);
      }
      for (int sample = 0; sample < 50; ++sample) {
        const Vec3 p = box.lo + (box.hi - box.lo).cwiseProduct(Vec3(t(rng), t(rng), t(rng)));
        lowest = std::min(lowest, obstacle_sdf(ob, origin, p).phi);
      }
      REQUIRE(bound <= lowest + 1e-12);
      if (bound > 0.5 * lowest && lowest > 0) ++tight;
    }
    // Not vacuous: far boxes get a useful (positive, same order) bound.
    MESSAGE(std::string(kNames[k]) << ": bound within a factor 2 of the sampled minimum for " << tight << " of 300 boxes");
    CHECK(tight > 30);
  }
}
