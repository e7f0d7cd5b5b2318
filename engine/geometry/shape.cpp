// Signed distance functions and bounds of the analytic primitives and their union.
#include "engine/geometry/shape.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {

namespace {

// q = |p| - b;  d = |max(q, 0)| + min(max_i q_i, 0)   (exact inside and outside)
double box_sdf(const Vec3& p, const Vec3& b) {
  const Vec3 q = p.cwiseAbs() - b;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Capped cylinder along y: d = (|p_xz| - r, |p_y| - h);
// sdf = min(max(d1, d2), 0) + |max(d, 0)|   (exact)
double cylinder_sdf(const Vec3& p, double r, double h) {
  const double d1 = std::hypot(p.x(), p.z()) - r;
  const double d2 = std::abs(p.y()) - h;
  return std::min(std::max(d1, d2), 0.0) + std::hypot(std::max(d1, 0.0), std::max(d2, 0.0));
}

// Capsule along y: distance to the segment y in [-h, h], minus r   (exact)
double capsule_sdf(const Vec3& p, double r, double h) {
  const double y = std::clamp(p.y(), -h, h);
  return (p - Vec3(0, y, 0)).norm() - r;
}

// Ellipsoid with semi-axes a: k0 = |p/a|, k1 = |p/a^2|, sdf ~ k0 (k0 - 1) / k1.
// This is one Newton step on |p/a| - 1 (its gradient has length k1/k0): exact on the
// surface and for spheres, with the exact sign everywhere because k0 - 1 carries it.
double ellipsoid_sdf(const Vec3& p, const Vec3& a) {
  const double k0 = p.cwiseQuotient(a).norm();
  const double k1 = p.cwiseQuotient(a.cwiseProduct(a)).norm();
  if (k1 == 0) return -a.minCoeff();  // the centre: the gradient vanishes there
  return k0 * (k0 - 1) / k1;
}

// World-space half extents of a local box with half extents e: sum_j |R_ij| e_j.
Vec3 rotated_half_extents(const Mat3& r, const Vec3& e) { return r.cwiseAbs() * e; }

}  // namespace

double Primitive::sdf(const Vec3& p) const {
  const Vec3 q = rotation.transpose() * (p - center);  // rotation is orthonormal: R^-1 = R^T
  switch (kind) {
    case PrimitiveKind::Box: return box_sdf(q, size);
    case PrimitiveKind::Sphere: return q.norm() - size.x();
    case PrimitiveKind::Cylinder: return cylinder_sdf(q, size.x(), size.y());
    case PrimitiveKind::Capsule: return capsule_sdf(q, size.x(), size.y());
    case PrimitiveKind::Ellipsoid: return ellipsoid_sdf(q, size);
  }
  return 1e300;
}

Aabb Primitive::bounds() const {
  Vec3 half = Vec3::Zero();
  const Vec3 axis = rotation.col(1);  // world direction of local y
  switch (kind) {
    case PrimitiveKind::Box: half = rotated_half_extents(rotation, size); break;
    case PrimitiveKind::Sphere: half = Vec3::Constant(size.x()); break;
    case PrimitiveKind::Cylinder:
      // Two end discs of radius r: a disc with unit normal n spans r sqrt(1 - n_i^2) along i.
      for (int i = 0; i < 3; ++i)
        half[i] = std::abs(axis[i]) * size.y() +
                  size.x() * std::sqrt(std::max(0.0, 1 - axis[i] * axis[i]));
      break;
    case PrimitiveKind::Capsule:
      // Segment of half length h swept by a ball of radius r.
      half = axis.cwiseAbs() * size.y() + Vec3::Constant(size.x());
      break;
    case PrimitiveKind::Ellipsoid:
      // Support of {R diag(a) u : |u| = 1} along e_i is |row_i(R diag(a))|.
      for (int i = 0; i < 3; ++i) half[i] = rotation.row(i).cwiseProduct(size.transpose()).norm();
      break;
  }
  Aabb b;
  b.lo = center - half;
  b.hi = center + half;
  return b;
}

double Shape::sdf(const Vec3& p) const {
  double d = 1e300;  // empty union: everything is outside
  for (const Primitive& part : parts) d = std::min(d, part.sdf(p));
  return d;
}

Aabb Shape::bounds() const {
  Aabb b;
  for (const Primitive& part : parts) {
    const Aabb pb = part.bounds();
    b.extend(pb.lo);
    b.extend(pb.hi);
  }
  return b;
}

PrimitiveKind parse_primitive_kind(const std::string& name, bool& ok) {
  ok = true;
  if (name == "box") return PrimitiveKind::Box;
  if (name == "sphere") return PrimitiveKind::Sphere;
  if (name == "cylinder") return PrimitiveKind::Cylinder;
  if (name == "capsule") return PrimitiveKind::Capsule;
  if (name == "ellipsoid") return PrimitiveKind::Ellipsoid;
  ok = false;
  return PrimitiveKind::Box;
}

const char* primitive_kind_name(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::Box: return "box";
    case PrimitiveKind::Sphere: return "sphere";
    case PrimitiveKind::Cylinder: return "cylinder";
    case PrimitiveKind::Capsule: return "capsule";
    case PrimitiveKind::Ellipsoid: return "ellipsoid";
  }
  return "box";
}

}  // namespace sinew
