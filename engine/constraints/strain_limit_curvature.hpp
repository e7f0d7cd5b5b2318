#pragma once
// Curvature of strain-limit rows for SQP: a positive semi-definite approximation of
// -d2C/dx2 over the tet's 12 coordinates, the constraints' part of the Lagrangian's
// Hessian. Without it the SQP iteration of a bending beam, whose rows carry large
// multipliers while the tets rotate, overshoots and diverges (Gauss-Newton on the
// constraints); energy limits have the same term (energy_limit.hpp).
//
// Isotropic rows depend on x through s_i(F) only; d2 s_i / dF2 in the frame of the SVD,
// a = U^T dF V:
//   d2 s_i[dF, dF] = sum_{j != i} (s_i (a_ij^2 + a_ji^2) + 2 s_j a_ij a_ji) / (s_i^2 - s_j^2)
// whose 2x2 blocks on (a_ij, a_ji) have the eigenvectors (1, -1)/sqrt2 ("twist",
// eigenvalue 1/(s_i + s_j)) and (1, 1)/sqrt2 ("flip", 1/(s_i - s_j)). A row C = (s_i - 1)
// + const (compress, sign -1 of -C) or const - (s_i - 1) (stretch) has -d2C = sign d2s_i;
// eigenvalues are clamped at 0 and |s_i - s_j|, |s_i + s_j| floored at kCurvatureGap, so
// the matrix stays bounded when singular values meet.
//
// The anisotropic modes depend on the principal directions too (c_ij = v_i . m_j), and
// that part dominates: a fibre stretched by 90 % whose neighbour axes are limited to 4 %
// is held within 2.5 degrees of them by its rows, whose Jacobian is then mostly the
// (s_i - 1) dc_ij term. With only the s_i part above, SQP on the paper's soft beam (fig.
// 2) cycled at 1-7 % past the limits in two thirds of its frames. Their curvature is the
// full Hessian in F by forward differences of the analytic dC/dF (strain_limit.hpp, exact
// where gaps exceed kStrainLimitGapTolerance), eigenvalues clamped at 0, then mapped to x.
// Forward, not central: 10 evaluations per tet instead of 18 (16 -> 9.3 us per tet, the
// flat finger's settle_curvature 1.24 -> 0.85 ms on 2 threads), at a step small enough
// (1e-8) that the O(step |d3C|) error stays below 4e-6 of the Hessian in the test's blended
// case (at 1e-7 it was 1.6e-5; round-off, ~1e-16 / step of dC/dF, is still far below).
// Bounded like the isotropic formula: where two stretches are closer than kCurvatureGap
// (relative) it is taken at the F with the same U, V and stretches that far apart (plus
// the probe step, so no probe swaps the axes' order: C has a kink where the i-th largest
// stretch changes axis). Closer, V turns like 1 / gap and the Hessian would grow with it.
#include <array>

#include "engine/constraints/strain_limit.hpp"
#include "engine/core/types.hpp"
#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat9 = Eigen::Matrix<double, 9, 9>;  // as engine/materials/material.hpp

constexpr double kCurvatureGap = 1e-2;
constexpr double kCurvatureStep = 1e-8;  // forward-difference step in F (dimensionless)

// Isotropic rows. `stretch`: the row bounds s_i from above.
Mat12 compute_isotropic_strain_limit_curvature(const RotationVariantSvd& svd, int i, bool stretch,
                                               const Mat43& dN_dX);

// d2C_k/dF2 (9 x 9 over vec(F), column-major) of every row in `rows` (evaluated at F, any
// mode), by forward differences of dC/dF, stretches kept apart as above; symmetrised. A
// pair cut's (strain_limit.hpp) is 0: it holds a direction fixed in the material, which
// the probes' own SVDs would turn. (Its Hessian, a (I - n n^T) / |F w| on w, is of the order
// of a well-separated row's; left out, the cuts are treated by Gauss-Newton.)
void strain_limit_hessians(const StrainLimitSpec& spec, const Mat3& F, const StrainLimitRows& rows,
                           std::array<Mat9, kStrainRowIndexCount>& hessians);

// The curvature block of every row in `rows`, in their order: the isotropic formula for
// isotropic limits, else -d2C/dF2 of strain_limit_hessians with eigenvalues clamped at 0.
void compute_strain_limit_curvatures(const StrainLimitSpec& spec, const Mat3& F, const Mat43& dN_dX,
                                     const StrainLimitRows& rows, std::array<Mat12, kStrainRowIndexCount>& out);

}  // namespace sinew
