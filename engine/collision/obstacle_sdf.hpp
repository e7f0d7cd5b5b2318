#pragma once
// Signed distance of the analytic obstacles (metres, positive on the free side) and its
// gradient, the unit outward normal. Kernels follow the ipc-toolkit habit of a value and
// its gradient together; tests check the normal against finite differences of phi.
#include "engine/core/types.hpp"
#include "engine/scene/scene.hpp"

namespace sinew {

struct SdfSample {
  double phi = 0;               // signed distance, m; < 0 inside the obstacle
  Vec3 normal = Vec3::UnitY();  // d phi / d p, unit length
};

// Plane through o with unit normal n: phi = (p - o) . n.
SdfSample plane_sdf(const Vec3& o, const Vec3& n, const Vec3& p);
// Sphere: phi = |p - c| - r, normal (p - c) / |p - c|.
SdfSample sphere_sdf(const Vec3& c, double r, const Vec3& p);
// Box with centre c, local-to-world rotation Q, half extents e (exact Euclidean distance).
SdfSample box_sdf(const Vec3& c, const Mat3& Q, const Vec3& e, const Vec3& p);
// Capsule: points within r of the segment c + Q (0, s, 0), |s| <= half_length.
SdfSample capsule_sdf(const Vec3& c, const Mat3& Q, double half_length, double r, const Vec3& p);

// The obstacle with its reference point (plane point / centre) at `origin`. A mesh is
// queried through its BVH, or triangle by triangle when `brute_force` (tests, benchmarks).
SdfSample obstacle_sdf(const ObstacleDesc& obstacle, const Vec3& origin, const Vec3& p, bool brute_force = false);

// Distance between two axis-aligned boxes (0 when they overlap).
double box_distance(const Aabb& a, const Aabb& b);

// A lower bound of phi over the box `box` (broad phase: no point of it is nearer than this).
double obstacle_distance_bound(const ObstacleDesc& obstacle, const Vec3& origin, const Aabb& box);

}  // namespace sinew
