#pragma once
// Where a kinematic obstacle is: its reference point (plane point / centre) at time t, and
// the velocity friction sees over a time step.
#include "engine/scene/scene.hpp"

namespace sinew {

// point + velocity t, or the keyframes interpolated linearly (held outside their span).
Vec3 obstacle_position(const ObstacleDesc& obstacle, double t);

// Mean velocity over [t0, t1]: (position(t1) - position(t0)) / (t1 - t0). Over a time step
// this is the velocity that moves the obstacle from where the step starts to where the
// contact rows place it (t1 = end of step), so the two agree.
Vec3 obstacle_velocity(const ObstacleDesc& obstacle, double t0, double t1);

}  // namespace sinew
