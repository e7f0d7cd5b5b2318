#include "render/camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace sinew {

Eigen::Matrix4f Camera::view() const {
  const Eigen::Vector3f f = (target - eye).normalized();
  const Eigen::Vector3f s = f.cross(up).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4f Camera::projection() const {
  const float t = 1.0f / std::tan(fov_y_deg * float(M_PI) / 360.0f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2 * far * near / (near - far);
  m(3, 2) = -1;
  return m;
}

Eigen::Vector2f Camera::to_pixel(const Vec3& p, int width, int height, bool* in_front) const {
  const Eigen::Vector4f clip = view_projection() * Eigen::Vector4f(p.x(), p.y(), p.z(), 1);
  if (in_front) *in_front = clip.w() > 0;
  const float x = clip.x() / clip.w(), y = clip.y() / clip.w();
  return {(x * 0.5f + 0.5f) * width, (0.5f - y * 0.5f) * height};
}

Vec3 orbit_reference(const Vec3& up) {
  const Vec3 axis = std::abs(up.z()) > 0.9 ? Vec3::UnitX() : Vec3::UnitZ();
  return (axis - axis.dot(up) * up).normalized();
}

Camera frame_box(const Aabb& box, const Vec3& up_in, double orbit_deg, double elevation_deg, double fov_y_deg,
                 double aspect) {
  const Vec3 up = up_in.normalized();
  const Vec3 centre = 0.5 * (box.lo + box.hi);
  const double radius = std::max(0.5 * (box.hi - box.lo).norm(), 1e-6);
  const Vec3 ref = orbit_reference(up), side = up.cross(ref);
  const double az = orbit_deg * M_PI / 180, el = elevation_deg * M_PI / 180;
  const Vec3 dir = std::cos(el) * (std::cos(az) * ref + std::sin(az) * side) + std::sin(el) * up;
  // The narrower of the two fields of view decides the distance.
  const double half_fov_y = fov_y_deg * M_PI / 360;
  const double half_fov_x = std::atan(std::tan(half_fov_y) * aspect);
  const double distance = radius / std::sin(std::min(half_fov_y, half_fov_x));

  Camera c;
  c.eye = (centre + distance * dir).cast<float>();
  c.target = centre.cast<float>();
  c.up = up.cast<float>();
  c.fov_y_deg = float(fov_y_deg);
  c.aspect = float(aspect);
  // Depth range covers the ground quad (a few radii around the scene, see ground_pass);
  // a far/near ratio of a few hundred keeps 24-bit depth precise.
  c.near = float(distance * 0.05);
  c.far = float(distance + 12 * radius);
  return c;
}

}  // namespace sinew
