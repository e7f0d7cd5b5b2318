#pragma once
// Rotation-variant SVD of a 3x3 matrix (Irving et al. 2004; paper 003, sec. 4.2;
// paper 001, sec. 3): F = U diag(S) V^T with det U = det V = +1. A reflection in F shows as
// a negative smallest singular value, S(2), instead of a reflection in U or V.
// S is sorted by absolute value, largest first. Finite for every finite F whose largest
// singular value is representable (up to about 1e308), including repeated, zero and subnormal
// singular values; a NaN or Inf in F gives NaN singular values (U = V = I). One-sided Jacobi
// underneath (rotation_variant_svd.cpp).
#include <Eigen/LU>

#include "engine/core/types.hpp"

namespace sinew {

struct RotationVariantSvd {
  Mat3 U;  // rotation
  Vec3 S;  // |S(0)| >= |S(1)| >= |S(2)|; only S(2) may be negative
  Mat3 V;  // rotation
};

RotationVariantSvd compute_rotation_variant_svd(const Mat3& F);
// out[k] = compute_rotation_variant_svd(F[k]) for k < count, bit for bit, four at a time on
// AVX2 (where one SVD's chain of roots and divisions would leave the vector units idle).
void compute_rotation_variant_svds(const Mat3* F, RotationVariantSvd* out, int count);

}  // namespace sinew
