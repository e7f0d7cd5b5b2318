#pragma once
// A triangle surface: vertices and counter-clockwise (outward) triangles.
#include "engine/core/types.hpp"

namespace sinew {

struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;

  Aabb bounds() const {
    Aabb b;
    for (const Vec3& p : vertices) b.extend(p);
    return b;
  }
};

// Edges shared by other than exactly two triangles (0 for a closed manifold surface).
int count_open_edges(const TriMesh& mesh);

}  // namespace sinew
