#include "render/scene_layout.hpp"

#include <Eigen/Geometry>
#include <limits>

namespace sinew {

Vec3 scene_up(const Model& model) {
  for (const ObstacleDesc& o : model.obstacles)
    if (o.type == "plane") return o.normal.normalized();
  if (model.gravity.norm() > 0) return -model.gravity.normalized();
  return Vec3::UnitY();
}

Aabb surface_bounds(const Model& model, const State& state) {
  Aabb box;
  for (size_t b = 0; b < model.bodies.size() && b < state.surface.size(); ++b)
    for (const Vec3& p : state.surface[b]) box.extend(p);
  return box;
}

GroundPlane choose_ground(const Model& model, const State& state) {
  for (const ObstacleDesc& o : model.obstacles)
    if (o.type == "plane") return {o.point, o.normal.normalized(), true};
  GroundPlane ground{Vec3::Zero(), scene_up(model), false};
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& surface : state.surface)
    for (const Vec3& p : surface)
      if (p.dot(ground.normal) < lowest) lowest = p.dot(ground.normal), ground.point = p;
  return ground;
}

Aabb framing_box(const Model& model, const State& state, const GroundPlane& ground) {
  const Aabb bodies = surface_bounds(model, state);
  if (bodies.empty()) return bodies;
  Aabb box = bodies;
  const double reach = 2 * (bodies.hi - bodies.lo).norm();
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1 ? bodies.hi : bodies.lo).x(), (corner & 2 ? bodies.hi : bodies.lo).y(),
                 (corner & 4 ? bodies.hi : bodies.lo).z());
    const double height = (p - ground.point).dot(ground.normal);
    if (height > 0 && height <= reach) box.extend(p - height * ground.normal);
  }
  return box;
}

}  // namespace sinew
