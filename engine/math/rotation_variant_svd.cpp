#include "engine/math/rotation_variant_svd.hpp"

#include <Eigen/SVD>

namespace sinew {

RotationVariantSvd compute_rotation_variant_svd(const Mat3& F) {
  const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationVariantSvd r{svd.matrixU(), svd.singularValues(), svd.matrixV()};
  // Eigen returns non-negative values sorted descending; move any reflection of U or V
  // into the smallest value so that both become rotations (U S V^T is unchanged).
  if (r.U.determinant() < 0) {
    r.U.col(2) *= -1;
    r.S(2) *= -1;
  }
  if (r.V.determinant() < 0) {
    r.V.col(2) *= -1;
    r.S(2) *= -1;
  }
  return r;
}

}  // namespace sinew
