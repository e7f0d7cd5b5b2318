#pragma once
// Closest point of a triangle to a point, with the feature it lies on (needed for the
// angle-weighted pseudo-normal that signs a mesh distance).
#include "engine/core/types.hpp"

namespace sinew {

// Features of triangle (a, b, c): its vertices, its edges ab, bc, ca, or its interior.
enum class TriangleFeature { A, B, C, AB, BC, CA, Face };

struct TriangleClosest {
  Vec3 point;
  TriangleFeature feature = TriangleFeature::Face;
  Vec3 bary = Vec3(1, 0, 0);  // point = bary[0] a + bary[1] b + bary[2] c
};

// The point of triangle abc nearest p, by the Voronoi regions of its vertices, edges and
// face (e.g. Ericson, Real-Time Collision Detection, sec. 5.1.5): with ab = b - a,
// ac = c - a, ap = p - a, d1 = ab.ap, d2 = ac.ap, ... p projects onto vertex a when
// d1 <= 0 and d2 <= 0, onto edge ab when its barycentric coordinate vc <= 0 with
// 0 <= d1 / (d1 - d3) <= 1, and so on; otherwise onto the face at barycentric (u, v, w).
TriangleClosest closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace sinew
