#pragma once
// Smooth per-vertex normals of a deformed triangle surface, recomputed every frame.
#include <Eigen/Core>
#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

// Each vertex gets the normalised sum of its triangles' unnormalised normals (area-weighted,
// so slivers barely count). Triangles are counter-clockwise seen from outside; a vertex in no
// triangle, or whose triangles cancel, gets (0, 0, 0).
void smooth_normals(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles,
                    std::vector<Eigen::Vector3f>& normals);

}  // namespace sinew
