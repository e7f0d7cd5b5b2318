#pragma once
// Basic numeric types shared by the whole engine.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace sinew {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

// Axis-aligned box.
struct Aabb {
  Vec3 lo = Vec3::Constant(1e300);
  Vec3 hi = Vec3::Constant(-1e300);
  void extend(const Vec3& p) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }
  bool empty() const { return (hi.array() < lo.array()).any(); }
};

}  // namespace sinew
