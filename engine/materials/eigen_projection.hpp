#pragma once
// Closed-form eigensystem of an isotropic material's Hessian d^2 Psi / dF^2 in the frame of the
// rotation-variant SVD F = U diag(sigma) V^T (paper 003, sec. 4; Teran et al. 2005). Writing
// Psi as a function of the signed singular values, psi(sigma), with psi_i = d psi / d sigma_i:
// - 3 scaling modes U diag(w) V^T, where (value, w) are the eigenpairs of the 3x3 symmetric
//   matrix d^2 psi / d sigma^2;
// - for each pair (i, j) with k the remaining axis (k = 0: (1, 2), k = 1: (0, 2), k = 2: (0, 1)):
//   twist U (e_i e_j^T - e_j e_i^T) V^T / sqrt 2, value (psi_i + psi_j) / (sigma_i + sigma_j),
//   flip  U (e_i e_j^T + e_j e_i^T) V^T / sqrt 2, value (psi_i - psi_j) / (sigma_i - sigma_j).
// Each material writes these quotients in closed form without the division where it can
// (the invariant materials can; corotational's twist cannot, see corotational.hpp).
// The nine eigenmatrices are orthonormal in the Frobenius product, so
// H = sum_m value_m vec(Q_m) vec(Q_m)^T and its projection to semi-definiteness clamps the values.
#include "engine/materials/material.hpp"
#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

// vec(M), column-major (the layout of Mat9 rows and columns).
inline Vec9 vec9(const Mat3& M) { return Eigen::Map<const Vec9>(M.data()); }

struct SvdEigensystem {
  RotationVariantSvd svd;
  Mat3 scaling = Mat3::Zero();  // d^2 psi / d sigma^2 (symmetric)
  Vec3 twist = Vec3::Zero();    // twist(k): eigenvalue of the twist about axis k
  Vec3 flip = Vec3::Zero();     // flip(k): eigenvalue of the flip about axis k
};

struct Eigenpairs {
  Vec9 values;    // 0-2 scaling, 3-5 twist (k = 0, 1, 2), 6-8 flip (k = 0, 1, 2)
  Mat9 vectors;   // column m = vec(Q_m), column-major vec; orthonormal
};

// The nine eigenpairs of the system (scaling block diagonalised by Eigen's 3x3 solver).
Eigenpairs compute_eigenpairs(const SvdEigensystem& system);

// sum_m value_m vec(Q_m) vec(Q_m)^T, with every value replaced by max(value, 0) when clamp.
Mat9 assemble_eigensystem(const SvdEigensystem& system, bool clamp);

// H, the matrix of `system` assembled some cheaper way, minus its negative modes:
// H - sum_{value_m < 0} value_m vec(Q_m) vec(Q_m)^T, which is assemble_eigensystem(system, true)
// up to round-off but builds only the modes it removes (near rest: none, or one twist).
Mat9 remove_negative_modes(const Mat9& H, const SvdEigensystem& system);
// The modes remove_negative_modes removes, in its order: values[m] < 0 and the eigenmatrix
// Q_m (unit Frobenius norm; the mode is vec(Q_m)). Returns their number.
struct NegativeModes {
  double values[9];
  Mat3 matrices[9];
};
int negative_modes(const SvdEigensystem& system, NegativeModes& modes);

// Nearest PSD matrix by a numerical eigen-decomposition (Eigen's SelfAdjointEigenSolver, values
// clamped at 0): the reference the closed form is tested against, and the fallback for a
// material without a closed-form eigensystem (none so far).
Mat9 project_numerically(const Mat9& H);

}  // namespace sinew
