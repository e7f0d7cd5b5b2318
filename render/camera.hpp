#pragma once
// A perspective look-at camera, and the default framing of a bounding box.
#include <Eigen/Core>

#include "engine/core/types.hpp"

namespace sinew {

struct Camera {
  Eigen::Vector3f eye = Eigen::Vector3f(0, 0, 1), target = Eigen::Vector3f::Zero(), up = Eigen::Vector3f::UnitY();
  float fov_y_deg = 40, aspect = 16.0f / 9.0f, near = 0.01f, far = 100;

  Eigen::Matrix4f view() const;
  Eigen::Matrix4f projection() const;
  Eigen::Matrix4f view_projection() const { return projection() * view(); }
  // Pixel position (x right, y down from the top-left corner, pixel centres at +0.5) of a
  // world point in a width x height image; also returns whether it lies in front of the camera.
  Eigen::Vector2f to_pixel(const Vec3& p, int width, int height, bool* in_front = nullptr) const;
};

// A camera that looks at the centre of `box` from azimuth `orbit_deg` around `up` (0: from
// the side the reference axis points to: +z, or +x if up is along z) and `elevation_deg` above
// the horizon, far enough that the box's bounding sphere fits the view both ways.
Camera frame_box(const Aabb& box, const Vec3& up, double orbit_deg, double elevation_deg, double fov_y_deg,
                 double aspect);

// A unit vector perpendicular to `up` that the orbit angle is measured from.
Vec3 orbit_reference(const Vec3& up);

}  // namespace sinew
