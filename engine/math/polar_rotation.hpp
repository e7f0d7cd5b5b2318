#pragma once
// Rotation part R of F = R S (det R = +1, S symmetric), the corotational elements' rotation
// (hex8, tet4). For det F > 0 it is the orthogonal polar factor, found by Newton's
// iteration; for inverted, nearly flat or non-finite F it is U V^T of the rotation-variant
// SVD (a reflection in F is left in S; a non-finite F gives R = I).
#include "engine/core/types.hpp"

namespace sinew {

Mat3 polar_rotation(const Mat3& F);

// The Newton part alone: R = the polar factor of F, and true, when F is finite with
// det F > 1e-3 of a rotation's at the same Frobenius norm (for singular values (1, 1, s):
// s > ~5.4e-4; for (s, 1, 1): s < ~72) and the iteration converges; else false and R
// untouched (polar_rotation then takes the SVD). For tests.
bool newton_polar_rotation(const Mat3& F, Mat3& R);

}  // namespace sinew
