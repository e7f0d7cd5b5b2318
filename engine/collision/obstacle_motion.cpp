#include "engine/collision/obstacle_motion.hpp"

#include <algorithm>

namespace sinew {

Vec3 obstacle_position(const ObstacleDesc& ob, double t) {
  const std::vector<ObstacleKeyframe>& k = ob.motion.keyframes;
  if (k.empty()) return ob.point + t * ob.motion.velocity;
  if (t <= k.front().t) return k.front().position;
  if (t >= k.back().t) return k.back().position;
  // First keyframe later than t; its predecessor is at or before t.
  const auto next = std::upper_bound(k.begin(), k.end(), t,
                                     [](double time, const ObstacleKeyframe& f) { return time < f.t; });
  const ObstacleKeyframe& a = *(next - 1);
  const double s = (t - a.t) / (next->t - a.t);
  return (1 - s) * a.position + s * next->position;
}

Vec3 obstacle_velocity(const ObstacleDesc& ob, double t0, double t1) {
  return (obstacle_position(ob, t1) - obstacle_position(ob, t0)) / (t1 - t0);
}

}  // namespace sinew
