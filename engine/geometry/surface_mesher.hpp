#pragma once
// Closed triangle surface of an analytic shape, for rendering and collision.
#include "engine/geometry/shape.hpp"
#include "engine/geometry/tri_mesh.hpp"

namespace sinew {

// Iso-surface SDF = 0 on a grid of spacing `resolution` over the shape's bounds.
// The result is closed, consistently oriented outward, with vertices shared.
TriMesh mesh_shape_surface(const Shape& shape, double resolution);

}  // namespace sinew
