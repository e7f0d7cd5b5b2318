#include <doctest/doctest.h>

#include "engine/collision/obstacle_motion.hpp"

using namespace sinew;

TEST_CASE("obstacle motion: static, constant velocity, and keyframes") {
  ObstacleDesc ob;
  ob.point = Vec3(1, 2, 3);
  CHECK((obstacle_position(ob, 5) - ob.point).norm() == 0);
  CHECK(obstacle_velocity(ob, 1, 1.1).norm() == 0);

  ob.motion.velocity = Vec3(0.5, 0, -1);
  CHECK((obstacle_position(ob, 2) - Vec3(2, 2, 1)).norm() < 1e-15);
  CHECK((obstacle_velocity(ob, 0.3, 0.4) - ob.motion.velocity).norm() < 1e-12);

  ob.motion.keyframes = {{1, Vec3(0, 0, 0)}, {2, Vec3(1, 0, 0)}, {4, Vec3(1, 2, 0)}};
  CHECK((obstacle_position(ob, 0) - Vec3(0, 0, 0)).norm() == 0);     // held before the first
  CHECK((obstacle_position(ob, 1.25) - Vec3(0.25, 0, 0)).norm() < 1e-15);
  CHECK((obstacle_position(ob, 2) - Vec3(1, 0, 0)).norm() == 0);     // on a keyframe
  CHECK((obstacle_position(ob, 3) - Vec3(1, 1, 0)).norm() < 1e-15);
  CHECK((obstacle_position(ob, 9) - Vec3(1, 2, 0)).norm() == 0);     // held after the last
  // Mean velocity over a step that straddles a keyframe: displacement / h.
  CHECK((obstacle_velocity(ob, 1.5, 2.5) - Vec3(0.5, 0.5, 0)).norm() < 1e-12);
  CHECK(obstacle_velocity(ob, 5, 6).norm() == 0);
}
