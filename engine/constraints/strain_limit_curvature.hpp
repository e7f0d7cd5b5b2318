#pragma once
// Curvature of a strain-limit row for SQP: a positive semi-definite approximation of
// -d2C/dx2 over the tet's 12 coordinates. Without it the SQP iteration of a bending beam,
// whose rows carry large multipliers while the tets rotate, overshoots and diverges
// (Gauss-Newton on the constraints); energy limits have the same term (energy_limit.hpp).
//
// C depends on x through s_i(F) (and, for the anisotropic modes, the principal direction
// v_i; that part is left out). d2 s_i / dF2 in the frame of the SVD, a = U^T dF V:
//   d2 s_i[dF, dF] = sum_{j != i} (s_i (a_ij^2 + a_ji^2) + 2 s_j a_ij a_ji) / (s_i^2 - s_j^2)
// whose 2x2 blocks on (a_ij, a_ji) have the eigenvectors (1, -1)/sqrt2 ("twist",
// eigenvalue 1/(s_i + s_j)) and (1, 1)/sqrt2 ("flip", 1/(s_i - s_j)). A row C = p (s_i - 1)
// + const (compress, sign -1 of -C) or const - p (s_i - 1) (stretch) has -d2C = sign p d2s_i;
// eigenvalues are clamped at 0 and |s_i - s_j|, |s_i + s_j| floored at kCurvatureGap, so
// the matrix stays bounded when singular values meet.
#include "engine/core/types.hpp"
#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat43 = Eigen::Matrix<double, 4, 3>;

constexpr double kCurvatureGap = 1e-2;

// `stretch`: the row bounds s_i from above; `p` >= 0 its coefficient of s_i.
Mat12 compute_strain_limit_curvature(const RotationVariantSvd& svd, int i, bool stretch, double p,
                                     const Mat43& dN_dX);

}  // namespace sinew
