#pragma once
// The one-sided Jacobi iteration under compute_rotation_variant_svd, in pieces that its
// scalar path and its four-lane AVX2 path (compute_rotation_variant_svds) share: the same
// preparation and finish, and sweeps whose every lane repeats the scalar operations in
// their order, so that both paths give the same bits (the build has no fused multiply-add).
#include <limits>

#include "engine/math/rotation_variant_svd.hpp"

namespace sinew::detail {

// Columns count as orthogonal when |cos| <= eps. Rounding can leave a cosine of a few eps
// after a rotation, which this test then rotates again (a tiny, harmless rotation): on
// 100,000 random F near I that never took more than 5 sweeps, 3-4 in all but 0.4 %.
constexpr double kOrthogonal = std::numeric_limits<double>::epsilon();
// More sweeps than one-sided Jacobi ever needs on a 3x3 matrix (it converges quadratically:
// 3-5 sweeps in double precision); the cap only guarantees termination.
constexpr int kMaxSweeps = 12;

// Columns of B = F V and of V as plain arrays: the rotations form a chain of dependent
// square roots and divisions, and Eigen's column blocks added about a quarter.
struct JacobiColumns {
  double b[3][3];
  double v[3][3];
};

// B = F / scale (scale: F's largest entry magnitude) and V = I. False when F needs no
// sweeps: r is then the result (NaN singular values for a non-finite F, zeros for F = 0).
bool prepare_jacobi(const Mat3& F, JacobiColumns& m, double& scale, RotationVariantSvd& r);
// Sweeps of the three column pairs until one rotates none (at most kMaxSweeps).
void jacobi_sweeps(JacobiColumns& m);
// The same on four matrices at once, lane by lane the scalar sweeps' operations (the CPU must
// have AVX2). A sweep that rotates nothing in some lane leaves it unchanged, so lanes that
// would have stopped earlier on their own end with the same bits.
void jacobi_sweeps4_avx2(JacobiColumns* m);
// U, S and V from the swept columns (sorted, det U = det V = +1).
void finish_jacobi(const JacobiColumns& m, double scale, RotationVariantSvd& r);

}  // namespace sinew::detail
