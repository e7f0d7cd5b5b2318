#pragma once
// Each body's embedded surface at the current positions as a signed-distance mesh, for
// body-vs-body contact: built on first use, then only refitted (the triangles never change).
#include <memory>
#include <vector>

#include "engine/collision/mesh_sdf.hpp"

namespace sinew {

struct Model;

struct BodySurfaces {
  std::vector<std::shared_ptr<MeshSdf>> mesh;  // per body; null until first needed
  std::vector<Vec3> scratch;                   // embedded positions being uploaded
};

// Body b's surface at node positions x (its BVH refitted to them).
const MeshSdf& deformed_surface(const Model& model, int b, const VecX& x, BodySurfaces& surfaces);

}  // namespace sinew
