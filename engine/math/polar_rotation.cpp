#include "engine/math/polar_rotation.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

bool newton_polar_rotation(const Mat3& F, Mat3& R) {
  // Newton's iteration X <- (z X + X^-T / z) / 2 maps each singular value s to
  // (z s + 1 / (z s)) / 2 and keeps the singular vectors, so it converges quadratically to
  // the polar factor U V^T, a rotation while det X > 0 (Higham 1986). z, the Frobenius
  // scaling (|X^-1| / |X|)^(1/2), balances the largest and smallest singular values in the
  // first iterations; it is dropped near convergence, where it is ~1 and only adds
  // round-off. Elements near rest take 3-4 iterations (about a third of the SVD's time).
  // F is first scaled by a power of two (exact; R does not depend on it) to a largest
  // entry in [0.5, 1), so that no norm, determinant or z over- or underflows.
  const double largest = F.cwiseAbs().maxCoeff();
  if (!(largest > 0) || !std::isfinite(largest)) return false;
  int exponent = 0;
  std::frexp(largest, &exponent);
  Mat3 X = F;
  for (int k = 0; k < 9; ++k) X(k) = std::ldexp(X(k), -exponent);
  // Below a determinant of 1e-3 of a rotation's at the same norm the singular values are
  // too far apart for the inverse to keep its digits: the SVD instead, as for det F <= 0.
  const double norm = X.norm();
  if (!(X.determinant() > 1e-3 * norm * norm * norm / (3 * std::sqrt(3.0)))) return false;
  bool scaled = true;
  for (int iteration = 0; iteration < 12; ++iteration) {
    Mat3 cofactor;  // X^-T = cofactor / det X
    cofactor.col(0) = X.col(1).cross(X.col(2));
    cofactor.col(1) = X.col(2).cross(X.col(0));
    cofactor.col(2) = X.col(0).cross(X.col(1));
    const Mat3 inverse_transpose = cofactor / X.col(0).dot(cofactor.col(0));
    const double z = scaled ? std::sqrt(inverse_transpose.norm() / X.norm()) : 1.0;
    const Mat3 next = 0.5 * (z * X + inverse_transpose / z);
    const double change = (next - X).squaredNorm();
    X = next;
    // A change of 1e-9 (relative to |X| ~ sqrt 3) leaves an error of ~1e-18: round-off.
    if (change < 1e-18) {
      R = X;
      return true;
    }
    if (change < 1e-4) scaled = false;
  }
  return false;
}

Mat3 polar_rotation(const Mat3& F) {
  Mat3 R;
  if (newton_polar_rotation(F, R)) return R;
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  return svd.U * svd.V.transpose();
}

}  // namespace sinew
