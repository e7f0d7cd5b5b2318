#include "engine/collision/obstacle_sdf.hpp"

#include <stdexcept>

#include "engine/collision/mesh_sdf.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {
namespace {

// Any unit vector: the direction of the gradient where it is undefined (a sphere's centre,
// a capsule's axis). phi is still correct there; only the normal is a choice.
const Vec3 kFallbackNormal = Vec3::UnitY();

double sign_of(double a) { return a < 0 ? -1.0 : 1.0; }

const MeshSdf& mesh_of(const ObstacleDesc& ob) {
  if (!ob.mesh) throw std::logic_error("mesh obstacle " + ob.json_path + " used before build_model() loaded it");
  return *ob.mesh;
}

// World bounds of the closed obstacles.
Aabb obstacle_bounds(const ObstacleDesc& ob, const Vec3& origin) {
  Vec3 half = Vec3::Zero();
  switch (ob.kind) {
    case ObstacleDesc::Kind::Plane: break;  // unbounded; handled by the caller
    case ObstacleDesc::Kind::Sphere: half = Vec3::Constant(ob.radius); break;
    // |Q| e: the half extents of the rotated box's bounds.
    case ObstacleDesc::Kind::Box: half = ob.rotation.cwiseAbs() * ob.half_extents; break;
    case ObstacleDesc::Kind::Capsule:
      half = ob.half_length * ob.rotation.col(1).cwiseAbs() + Vec3::Constant(ob.radius);
      break;
    case ObstacleDesc::Kind::Mesh: {
      // The mesh was placed with its reference point at ob.point; it has moved by origin - point.
      const Aabb placed = mesh_of(ob).bounds();
      return {placed.lo + (origin - ob.point), placed.hi + (origin - ob.point)};
    }
  }
  Aabb box;
  box.extend(origin - half);
  box.extend(origin + half);
  return box;
}

}  // namespace

double box_distance(const Aabb& a, const Aabb& b) { return (a.lo - b.hi).cwiseMax(b.lo - a.hi).cwiseMax(0.0).norm(); }

SdfSample plane_sdf(const Vec3& o, const Vec3& n, const Vec3& p) { return {(p - o).dot(n), n}; }

SdfSample sphere_sdf(const Vec3& c, double r, const Vec3& p) {
  const Vec3 d = p - c;
  const double len = d.norm();
  return {len - r, len > 0 ? Vec3(d / len) : kFallbackNormal};
}

// In box coordinates q = Q^T (p - c), with d = |q| - e per axis:
//   outside (some d_i > 0): phi = |max(d, 0)|, gradient sign(q) max(d, 0) / phi;
//   inside (all d_i <= 0):  phi = max_i d_i (the nearest face), gradient sign(q_i) e_i of
//   that face (the lowest axis on ties, so the choice is deterministic).
SdfSample box_sdf(const Vec3& c, const Mat3& Q, const Vec3& e, const Vec3& p) {
  const Vec3 q = Q.transpose() * (p - c);
  const Vec3 d = q.cwiseAbs() - e;
  const Vec3 out = d.cwiseMax(0.0);
  const Vec3 s(sign_of(q.x()), sign_of(q.y()), sign_of(q.z()));
  SdfSample r;
  if ((d.array() > 0).any()) {
    r.phi = out.norm();
    r.normal = Q * s.cwiseProduct(out / r.phi);
  } else {
    int axis = 0;
    r.phi = d.maxCoeff(&axis);
    r.normal = Q * (s[axis] * Vec3::Unit(axis));
  }
  return r;
}

// Nearest point of the axis segment: c + Q (0, clamp(q_y, -L, L), 0); then as a sphere.
SdfSample capsule_sdf(const Vec3& c, const Mat3& Q, double half_length, double r, const Vec3& p) {
  const Vec3 q = Q.transpose() * (p - c);
  const Vec3 d(q.x(), q.y() - std::clamp(q.y(), -half_length, half_length), q.z());
  const double len = d.norm();
  // On the axis the gradient is undefined: take the local x direction.
  return {len - r, len > 0 ? Vec3(Q * (d / len)) : Vec3(Q.col(0))};
}

SdfSample obstacle_sdf(const ObstacleDesc& ob, const Vec3& origin, const Vec3& p, bool brute_force) {
  switch (ob.kind) {
    case ObstacleDesc::Kind::Plane: return plane_sdf(origin, ob.normal, p);
    case ObstacleDesc::Kind::Sphere: return sphere_sdf(origin, ob.radius, p);
    case ObstacleDesc::Kind::Box: return box_sdf(origin, ob.rotation, ob.half_extents, p);
    case ObstacleDesc::Kind::Capsule: return capsule_sdf(origin, ob.rotation, ob.half_length, ob.radius, p);
    // Translated rigidly with its reference point: phi_t(p) = phi_0(p - (origin - point)).
    case ObstacleDesc::Kind::Mesh: {
      const Vec3 q = p - (origin - ob.point);
      return brute_force ? mesh_of(ob).sdf_brute_force(q) : mesh_of(ob).sdf(q);
    }
  }
  return {};
}

// Plane: the lowest corner, (centre - o) . n - sum_i |n_i| half_i. Closed obstacles:
// outside, phi(p) >= distance from p to the obstacle's bounds >= distance between the two
// boxes; where the boxes overlap, phi >= -(the obstacle's inradius): -r for a sphere or
// capsule, -min_i e_i for a box, at least -1/2 the smallest extent of the bounds for a mesh.
double obstacle_distance_bound(const ObstacleDesc& ob, const Vec3& origin, const Aabb& box) {
  if (ob.kind == ObstacleDesc::Kind::Plane) {
    const Vec3 centre = 0.5 * (box.lo + box.hi), half = 0.5 * (box.hi - box.lo);
    return (centre - origin).dot(ob.normal) - ob.normal.cwiseAbs().dot(half);
  }
  const double gap = box_distance(box, obstacle_bounds(ob, origin));
  if (gap > 0) return gap;
  if (ob.kind == ObstacleDesc::Kind::Mesh) {
    const Aabb bounds = mesh_of(ob).bounds();
    return -0.5 * (bounds.hi - bounds.lo).minCoeff();
  }
  return ob.kind == ObstacleDesc::Kind::Box ? -ob.half_extents.minCoeff() : -ob.radius;
}

}  // namespace sinew
