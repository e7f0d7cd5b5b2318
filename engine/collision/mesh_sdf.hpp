#pragma once
// Signed distance to a closed triangle mesh: the nearest point from TriangleBvh, signed by
// the angle-weighted pseudo-normal of the feature it lies on (Baerentzen & Aanaes 2005:
// for a closed, consistently oriented mesh, (p - c) . N has the sign of the distance for
// N the face normal, the sum of the two face normals at an edge, or the angle-weighted sum
// of the face normals at a vertex). Pseudo-normals are evaluated at query time from the
// current vertices, so a deforming mesh (a body's embedded surface) only refits its BVH.
#include <limits>
#include <memory>

#include "engine/collision/obstacle_sdf.hpp"
#include "engine/collision/triangle_bvh.hpp"
#include "engine/geometry/tri_mesh.hpp"

namespace sinew {

struct MeshDistance {
  double phi = std::numeric_limits<double>::infinity();  // signed; +inf when nothing was in range
  Vec3 normal = Vec3::UnitY();  // grad phi: sign (p - c) / |p - c|, the pseudo-normal on the surface
  int triangle = -1;            // nearest triangle, -1 when none within the search distance
  Vec3 bary = Vec3::Zero();     // of the nearest point c in that triangle
};

class MeshSdf {
 public:
  // `deforming`: update() will move the vertices (the BVH is built for refitting).
  explicit MeshSdf(const TriMesh& mesh, bool deforming = false);

  // New vertex positions, same triangles: refits the BVH.
  void update(const std::vector<Vec3>& vertices) { m_bvh.update(vertices); }

  // Nearest point within max_distance, signed. Through the Embree BVH / every triangle.
  MeshDistance distance(const Vec3& p, double max_distance = std::numeric_limits<double>::infinity()) const;
  MeshDistance distance_brute_force(const Vec3& p,
                                    double max_distance = std::numeric_limits<double>::infinity()) const;
  SdfSample sdf(const Vec3& p) const;
  SdfSample sdf_brute_force(const Vec3& p) const;

  const std::vector<Vec3>& vertices() const { return m_bvh.vertices(); }
  const std::vector<std::array<int, 3>>& triangles() const { return m_bvh.triangles(); }
  Aabb bounds() const { return m_bvh.bounds(); }

 private:
  Vec3 face_normal(int t) const;
  Vec3 pseudo_normal(int t, TriangleFeature feature) const;
  MeshDistance signed_result(const Vec3& p, const NearestTriangle& nearest) const;
  TriangleBvh m_bvh;
  std::vector<std::array<int, 3>> m_neighbour;  // per triangle edge ab, bc, ca: the other triangle, -1 if open
  std::vector<int> m_ring_begin, m_ring;        // per vertex: its triangles (CSR)
};

// Reads an OBJ obstacle, places it (x = center + R scale x_obj) and builds its MeshSdf.
std::shared_ptr<const MeshSdf> load_mesh_obstacle(const ObstacleDesc& obstacle);

}  // namespace sinew
