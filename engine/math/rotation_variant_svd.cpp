#include "engine/math/rotation_variant_svd.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "engine/core/cpu_features.hpp"
#include "engine/math/jacobi_columns.hpp"

namespace sinew {

namespace {

void swap_columns(Mat3& B, Mat3& V, Vec3& norm, int i, int j) {
  B.col(i).swap(B.col(j));
  V.col(i).swap(V.col(j));
  std::swap(norm(i), norm(j));
}

// (x, y) <- (c x - s y, s x + c y), entrywise.
void rotate(double* x, double* y, double c, double s) {
  for (int k = 0; k < 3; ++k) {
    const double a = x[k], b = y[k];
    x[k] = c * a - s * b;
    y[k] = s * a + c * b;
  }
}

// Rotates columns p and q of B (and of V alike) so that they become orthogonal, unless they
// already are to working precision. Returns whether it rotated. B's entries are at most 1
// in magnitude (F scaled), so the squares below neither overflow nor matter when they
// underflow (a column below 1e-154 is zero to working precision).
// jacobi_sweeps4_avx2 (rotation_variant_svd_avx2.cpp) repeats these operations in this
// order, lane by lane: change both or neither.
bool orthogonalize_pair(detail::JacobiColumns& m, int p, int q) {
  double* bp = m.b[p];
  double* bq = m.b[q];
  const double alpha = bp[0] * bp[0] + bp[1] * bp[1] + bp[2] * bp[2];
  const double beta = bq[0] * bq[0] + bq[1] * bq[1] + bq[2] * bq[2];
  const double gamma = bp[0] * bq[0] + bp[1] * bq[1] + bp[2] * bq[2];
  // A zero column gives gamma = 0: nothing to do, and no division below.
  if (gamma * gamma <= detail::kOrthogonal * detail::kOrthogonal * alpha * beta) return false;
  // The rotation angle theta with tan(2 theta) = 2 gamma / d, d = beta - alpha,
  // |theta| <= pi/4. With r = sqrt(d^2 + 4 gamma^2), cos(theta) = sqrt((r + |d|) / 2r) and
  // sin(theta) = sign(d) gamma / (r cos(theta)): both are (r + |d|, sign(d) 2 gamma) over
  // sqrt(2 r (r + |d|)): two roots and one division in a chain, where the route through
  // t = tan(theta) takes two of each (the SVD took a quarter longer).
  const double d = beta - alpha;
  const double r = std::sqrt(d * d + 4 * gamma * gamma);
  const double w = std::sqrt(2 * r * (r + std::abs(d)));
  if (!(w > 0)) return false;  // gamma^2 > 0 above, so only columns too short to matter
  const double inverse_w = 1 / w;
  const double c = (r + std::abs(d)) * inverse_w, s = (d < 0 ? -2 * gamma : 2 * gamma) * inverse_w;
  rotate(bp, bq, c, s);
  rotate(m.v[p], m.v[q], c, s);
  return true;
}

}  // namespace

namespace detail {

void jacobi_sweeps(JacobiColumns& m) {
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    bool rotated = orthogonalize_pair(m, 0, 1);
    rotated |= orthogonalize_pair(m, 0, 2);
    rotated |= orthogonalize_pair(m, 1, 2);
    if (!rotated) break;
  }
}

bool prepare_jacobi(const Mat3& F, JacobiColumns& m, double& scale, RotationVariantSvd& r) {
  if (!F.allFinite()) {  // garbage in shows as NaN out, for the callers' NaN checks
    r = {Mat3::Identity(), Vec3::Constant(std::numeric_limits<double>::quiet_NaN()), Mat3::Identity()};
    return false;
  }
  scale = F.cwiseAbs().maxCoeff();
  if (scale == 0) {
    r = {Mat3::Identity(), Vec3::Zero(), Mat3::Identity()};
    return false;
  }
  // Times the reciprocal, or divided where the reciprocal overflows (a subnormal scale,
  // below 1 / DBL_MAX). Kept a multiplication otherwise: dividing changes the last bits, and
  // paper 001's beam (whose SQP ends at its iteration cap in a quarter of its steps) then
  // crossed its strain tolerance by 1.6 % in one frame (docs/ARCHITECTURE.md, "Open: ...").
  const double inverse_scale = 1 / scale;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m.v[j][i] = i == j ? 1.0 : 0.0;
  if (std::isfinite(inverse_scale)) {
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) m.b[j][i] = F(i, j) * inverse_scale;
  } else {
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) m.b[j][i] = F(i, j) / scale;
  }
  return true;
}

void finish_jacobi(const JacobiColumns& m, double scale, RotationVariantSvd& r) {
  Mat3 B;
  Mat3& V = r.V;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      B(i, j) = m.b[j][i];
      V(i, j) = m.v[j][i];
    }
  // Columns by decreasing norm; a swap is a reflection of V, so an odd number of them is
  // undone by negating the last column of V and of B (F V = B still holds).
  Vec3 norm(B.col(0).norm(), B.col(1).norm(), B.col(2).norm());
  bool odd = false;
  if (norm(0) < norm(1)) swap_columns(B, V, norm, 0, 1), odd = !odd;
  if (norm(0) < norm(2)) swap_columns(B, V, norm, 0, 2), odd = !odd;
  if (norm(1) < norm(2)) swap_columns(B, V, norm, 1, 2), odd = !odd;
  if (odd) {
    V.col(2) = -V.col(2);
    B.col(2) = -B.col(2);
  }
  // U's first two columns from B's, its third their cross product (so det U = +1); the
  // third singular value is then B's last column along it, negative for a reflection.
  // Columns too short to give a direction (rank-deficient F) take any orthogonal one: the
  // singular value they would multiply is zero to working precision.
  Mat3& U = r.U;
  // The scaled F has an entry of magnitude 1 and rotations keep its Frobenius norm, so the
  // longest column is at least 1 / sqrt(3) long.
  U.col(0) = B.col(0) / norm(0);
  Vec3 u1 = B.col(1) - U.col(0).dot(B.col(1)) * U.col(0);
  const double n1 = u1.norm();
  U.col(1) = n1 > 1e-150 ? Vec3(u1 / n1) : Vec3(U.col(0).unitOrthogonal());
  U.col(2) = U.col(0).cross(U.col(1));
  const double s1 = n1 > 1e-150 ? norm(1) : 0.0;
  const double s2 = U.col(2).dot(B.col(2));  // |s2| <= norm(2) <= s1 up to round-off: keep the order exact
  r.S = scale * Vec3(norm(0), s1, std::copysign(std::min(std::abs(s2), s1), s2));
}

}  // namespace detail

// One-sided (Hestenes) Jacobi: plane rotations applied to the columns of F, accumulated in V,
// until the columns of B = F V are mutually orthogonal; then B = U diag(S). It reaches the
// singular values to a few ulps of the largest (Eigen's two-sided JacobiSVD, before: 900 ns
// a call against 590 ns, on the strain limits' and the hyperelastic Hessians' hot paths).
// F is scaled by its largest entry first, so no square overflows (an underflowing one belongs
// to a column below 1e-154 of the largest, zero to working precision).
RotationVariantSvd compute_rotation_variant_svd(const Mat3& F) {
  RotationVariantSvd r;
  detail::JacobiColumns m;
  double scale = 0;
  if (!detail::prepare_jacobi(F, m, scale, r)) return r;
  detail::jacobi_sweeps(m);
  detail::finish_jacobi(m, scale, r);
  return r;
}

void compute_rotation_variant_svds(const Mat3* F, RotationVariantSvd* out, int count) {
  if (!use_avx2()) {
    for (int k = 0; k < count; ++k) out[k] = compute_rotation_variant_svd(F[k]);
    return;
  }
  // Four at a time, each lane the scalar path's operations (the same bits); a last group of
  // fewer padded with zero columns, which no sweep rotates.
  for (int first = 0; first < count; first += 4) {
    detail::JacobiColumns m[4];
    double scale[4] = {0, 0, 0, 0};
    bool swept[4] = {false, false, false, false};
    for (int l = 0; l < 4; ++l) {
      if (first + l < count) swept[l] = detail::prepare_jacobi(F[first + l], m[l], scale[l], out[first + l]);
      if (!swept[l]) m[l] = detail::JacobiColumns{};
    }
    detail::jacobi_sweeps4_avx2(m);
    for (int l = 0; l < 4; ++l)
      if (swept[l]) detail::finish_jacobi(m[l], scale[l], out[first + l]);
  }
}

}  // namespace sinew
