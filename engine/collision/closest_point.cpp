#include "engine/collision/closest_point.hpp"

namespace sinew {

TriangleClosest closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  using F = TriangleFeature;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, F::A, Vec3(1, 0, 0)};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, F::B, Vec3(0, 1, 0)};
  // Edge ab: the barycentric coordinate of c, vc = d1 d4 - d3 d2, is <= 0.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, F::AB, Vec3(1 - v, v, 0)};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, F::C, Vec3(0, 0, 1)};
  // Edge ca: vb = d5 d2 - d1 d6 <= 0.
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, F::CA, Vec3(1 - w, 0, w)};
  }
  // Edge bc: va = d3 d6 - d5 d4 <= 0.
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), F::BC, Vec3(0, 1 - w, w)};
  }
  // Interior: barycentric (1 - v - w, v, w).
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {a + v * ab + w * ac, F::Face, Vec3(1 - v - w, v, w)};
}

}  // namespace sinew
