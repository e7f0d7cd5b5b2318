#pragma once
// Nearest-triangle queries over a triangle mesh: an Embree BVH traversed by rtcPointQuery,
// and the same answer by testing every triangle (kept for tests and benchmarks). The BVH
// can be refitted when the vertices move and the triangles stay (deformed surfaces).
#include <embree3/rtcore.h>

#include <limits>

#include "engine/collision/closest_point.hpp"

namespace sinew {

struct NearestTriangle {
  int triangle = -1;  // -1: none within the search distance
  TriangleClosest closest;
  double distance_sq = std::numeric_limits<double>::infinity();
};

struct RayHit {
  int triangle = -1;  // -1: the ray misses every triangle
  double t = std::numeric_limits<double>::infinity();  // hit point = origin + t direction
  Vec3 barycentric = Vec3::Zero();  // weights of the triangle's three vertices
};

class TriangleBvh {
 public:
  // `deforming`: update() will move the vertices; the BVH is then built for refitting
  // (RTC_BUILD_QUALITY_REFIT) instead of for query speed.
  TriangleBvh(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles, bool deforming);
  ~TriangleBvh();
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  // New vertex positions (same count and triangles); refits the BVH.
  void update(const std::vector<Vec3>& vertices);

  // Nearest triangle within max_distance of p (distances computed in double on the
  // double vertices; the float BVH only culls, with a slack for its rounding). Thread-safe.
  NearestTriangle nearest(const Vec3& p, double max_distance = std::numeric_limits<double>::infinity()) const;
  NearestTriangle nearest_brute_force(const Vec3& p,
                                      double max_distance = std::numeric_limits<double>::infinity()) const;

  // First triangle the ray origin + t direction (t >= 0) crosses (Embree rtcIntersect1;
  // picking a surface point under the cursor). Thread-safe.
  RayHit raycast(const Vec3& origin, const Vec3& direction) const;

  const std::vector<Vec3>& vertices() const { return m_vertices; }
  const std::vector<std::array<int, 3>>& triangles() const { return m_triangles; }
  Aabb bounds() const;

 private:
  void upload_vertices();
  std::vector<Vec3> m_vertices;
  std::vector<std::array<int, 3>> m_triangles;
  RTCDevice m_device = nullptr;
  RTCScene m_scene = nullptr;
  RTCGeometry m_geometry = nullptr;
  float* m_vertex_buffer = nullptr;  // owned by m_geometry
  double m_extent = 0;               // largest |coordinate| of a vertex (float rounding scale)
};

}  // namespace sinew
