#pragma once
// What every drawing pass of one frame needs to know about the view.
#include <Eigen/Core>

#include "render/camera.hpp"
#include "render/scene_layout.hpp"

namespace sinew {

struct ViewSetup {
  Camera camera;
  Eigen::Matrix4f view_projection;
  Eigen::Vector3f light;   // unit, towards the (directional) light; also casts the shadow
  GroundPlane ground;
  Vec3 scene_centre = Vec3::Zero();
  double scene_radius = 1;  // of the framed box's bounding sphere
  int width = 0, height = 0;
};

}  // namespace sinew
