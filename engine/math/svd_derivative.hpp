#pragma once
// Derivatives of the rotation-variant SVD F = U diag(S) V^T (engine/math/rotation_variant_svd.hpp)
// after Papadopoulo & Lourakis (ECCV 2000), as used by paper 001, eqs. 13-15.
//
// Differentiating F = U S V^T along a direction dF and writing the rotations' changes as
//   dU = U Omega_U,  dV = V Omega_V   (Omega_U, Omega_V antisymmetric)
// gives  A := U^T dF V = Omega_U S + dS - S Omega_V. Its diagonal is
//   dS_k = A_kk = u_k^T dF v_k                                        (paper 001, eq. 13)
// and each pair k < l gives a 2x2 system in a = Omega_U(k,l), b = Omega_V(k,l):
//   [ s_l  -s_k ] [a]   [A_kl]
//   [-s_k   s_l ] [b] = [A_lk],   determinant s_l^2 - s_k^2.
// With sym = (A_kl + A_lk)/2 and skew = (A_kl - A_lk)/2 its solution splits as
//   a = sym / (s_l - s_k) + skew / (s_l + s_k)
//   b = sym / (s_l - s_k) - skew / (s_l + s_k)
// so repeated singular values (s_k = s_l) blow up the symmetric part and a pair summing to
// zero (two zero values, or s_1 = -s_2 once S(2) turned negative) the antisymmetric part.
//
// Departure from the paper: it writes dV = -V Omega_v (eq. 14); here dV = V Omega_V, the same
// thing with Omega_V = -Omega_v.
//
// Repeated and zero singular values. There U and V are not unique and their true derivative
// is unbounded. Every denominator is clamped away from zero:
//   eps = gap_tolerance * max(|S(0)|, 1)
//   (s_l - s_k) -> min(s_l - s_k, -eps),  (s_l + s_k) -> max(s_l + s_k, eps)
// (for k < l the ordering |S(0)| >= |S(1)| >= |S(2)|, S(0), S(1) >= 0 gives s_l - s_k <= 0 and
// s_l + s_k >= 0, so the sign of each denominator is never in doubt). Hence:
//   - the result is exact when every gap |s_k - s_l| and sum |s_k + s_l| is at least eps;
//   - closer than eps it is the derivative with the gap widened to eps: continuous in F,
//     |Omega(k,l)| <= (|A_kl| + |A_lk|) / eps, always finite for finite F (no NaN, ever);
//   - dS is never regularised (singular values are Lipschitz in F even where they repeat).
#include "engine/core/types.hpp"
#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

// Default relative gap below which the coupling of a pair of singular values is clamped.
constexpr double kSvdGapTolerance = 1e-8;

// The differential of U, S, V along one direction dF.
struct SvdDifferential {
  Mat3 dU;       // U Omega_U
  Vec3 dS;       // u_k^T dF v_k
  Mat3 dV;       // V Omega_V
  Mat3 omega_U;  // antisymmetric
  Mat3 omega_V;  // antisymmetric
};

SvdDifferential compute_svd_differential(const RotationVariantSvd& svd, const Mat3& dF,
                                         double gap_tolerance = kSvdGapTolerance);

// All nine partial derivatives: entry [r][c] is d/dF(r, c), the differential along
// dF = e_r e_c^T. dS[r][c](k) = U(r, k) V(c, k).
struct SvdDerivative {
  Vec3 dS[3][3];
  Mat3 dU[3][3];
  Mat3 dV[3][3];
};

SvdDerivative compute_svd_derivative(const RotationVariantSvd& svd,
                                     double gap_tolerance = kSvdGapTolerance);

// Only V's rotation rate: Omega_V's entries (0, 1), (0, 2), (1, 2) along each dF = e_r e_c^T
// (dV[r][c] = V Omega_V). A linear functional of dV, <dV, W>, is then <Omega_V, V^T W>:
// three products per entry instead of nine, and no 3 x 3 product per entry to form dV
// (the strain limits' Jacobians, strain_limit.cpp).
struct SvdRotationDerivative {
  Vec3 omega_V[3][3];
};

SvdRotationDerivative compute_svd_rotation_derivative(const RotationVariantSvd& svd,
                                                      double gap_tolerance = kSvdGapTolerance);

}  // namespace sinew
