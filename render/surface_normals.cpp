#include "render/surface_normals.hpp"

#include <Eigen/Geometry>

namespace sinew {

void smooth_normals(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles,
                    std::vector<Eigen::Vector3f>& normals) {
  std::vector<Vec3> sum(vertices.size(), Vec3::Zero());
  for (const auto& t : triangles) {
    const Vec3 n = (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
    for (int i : t) sum[i] += n;
  }
  normals.resize(vertices.size());
  for (size_t i = 0; i < sum.size(); ++i) {
    const double length = sum[i].norm();
    normals[i] = length > 0 ? Eigen::Vector3f((sum[i] / length).cast<float>()) : Eigen::Vector3f::Zero();
  }
}

}  // namespace sinew
