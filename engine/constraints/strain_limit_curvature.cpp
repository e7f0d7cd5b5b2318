#include "engine/constraints/strain_limit_curvature.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {
namespace {

// Floors |d| at kCurvatureGap keeping its sign (0 counts as positive).
double floored(double d) { return d < 0 ? std::min(d, -kCurvatureGap) : std::max(d, kCurvatureGap); }

}  // namespace

Mat12 compute_strain_limit_curvature(const RotationVariantSvd& svd, int i, bool stretch, double p,
                                     const Mat43& dN_dX) {
  const double sign = stretch ? 1.0 : -1.0;
  Eigen::Matrix<double, 9, 9> H = Eigen::Matrix<double, 9, 9>::Zero();
  for (int j = 0; j < 3; ++j) {
    if (j == i) continue;
    const double twist = sign * p / floored(svd.S[i] + svd.S[j]);
    const double flip = sign * p / floored(svd.S[i] - svd.S[j]);
    // vec(U (E_ij -+ E_ji) V^T) / sqrt 2, column-major like F.
    const Mat3 Eij = svd.U.col(i) * svd.V.col(j).transpose(), Eji = svd.U.col(j) * svd.V.col(i).transpose();
    const Mat3 T = (Eij - Eji) / std::sqrt(2.0), L = (Eij + Eji) / std::sqrt(2.0);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> t(T.data()), l(L.data());
    if (twist > 0) H += twist * t * t.transpose();
    if (flip > 0) H += flip * l * l.transpose();
  }
  // x-space: dvec(F)/dx = B with B(r + 3c, 3a + r) = dN_a,c.
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
  for (int a = 0; a < 4; ++a)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) B(r + 3 * c, 3 * a + r) = dN_dX(a, c);
  return B.transpose() * H * B;
}

}  // namespace sinew
