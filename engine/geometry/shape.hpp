#pragma once
// Analytic solids for procedural bodies: primitives and their union, as signed distance
// functions (negative inside). The union's SDF is the minimum of its members' (exact
// outside, a bound inside), which is all voxelization and surface meshing need.
#include <string>

#include "engine/core/types.hpp"

namespace sinew {

enum class PrimitiveKind { Box, Sphere, Cylinder, Capsule, Ellipsoid };

struct Primitive {
  PrimitiveKind kind = PrimitiveKind::Box;
  // Box: half extents. Sphere: radius in x. Ellipsoid: semi-axes.
  // Cylinder, capsule: radius in x, half length (of the axis segment) in y; axis is local y.
  Vec3 size = Vec3::Constant(0.5);
  Vec3 center = Vec3::Zero();   // world position of the local origin
  Mat3 rotation = Mat3::Identity();  // local to world
  double sdf(const Vec3& p) const;   // world point
  Aabb bounds() const;
};

struct Shape {
  std::vector<Primitive> parts;  // union
  double sdf(const Vec3& p) const;
  Aabb bounds() const;
};

PrimitiveKind parse_primitive_kind(const std::string& name, bool& ok);
const char* primitive_kind_name(PrimitiveKind kind);

}  // namespace sinew
