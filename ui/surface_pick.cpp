#include "ui/surface_pick.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <numbers>

#include "engine/collision/triangle_bvh.hpp"

namespace sinew {

void pixel_ray(const Camera& camera, float x, float y, int width, int height, Vec3& origin, Vec3& direction) {
  const Vec3 eye = camera.eye.cast<double>();
  const Vec3 forward = (camera.target.cast<double>() - eye).normalized();
  const Vec3 right = forward.cross(camera.up.cast<double>()).normalized();
  const Vec3 up = right.cross(forward);
  const double half = std::tan(0.5 * camera.fov_y_deg * std::numbers::pi / 180.0);
  const double ndc_x = 2.0 * x / width - 1.0, ndc_y = 1.0 - 2.0 * y / height;
  origin = eye;
  direction = (forward + ndc_x * half * camera.aspect * right + ndc_y * half * up).normalized();
}

std::optional<Attachment> pick_surface(const Model& model, const State& state, const Vec3& origin,
                                       const Vec3& direction) {
  std::optional<Attachment> best;
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const auto& triangles = model.bodies[b].rest_surface.triangles;
    if (triangles.empty() || b >= state.surface.size()) continue;
    const TriangleBvh bvh(state.surface[b], triangles, false);
    const RayHit hit = bvh.raycast(origin, direction);
    if (hit.triangle < 0 || hit.t >= nearest) continue;
    nearest = hit.t;
    int corner = 0;
    hit.barycentric.maxCoeff(&corner);
    best = Attachment{int(b), triangles[size_t(hit.triangle)][size_t(corner)], Vec3::Zero()};
    best->target = state.surface[b][size_t(best->vertex)];
  }
  return best;
}

Attachment nearest_surface_vertex(const Model& model, const State& state, const Vec3& p) {
  Attachment best;
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t b = 0; b < model.bodies.size() && b < state.surface.size(); ++b)
    for (size_t v = 0; v < state.surface[b].size(); ++v)
      if (const double d = (state.surface[b][v] - p).squaredNorm(); d < nearest) {
        nearest = d;
        best = {int(b), int(v), state.surface[b][v]};
      }
  return best;
}

}  // namespace sinew
