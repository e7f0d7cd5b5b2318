#pragma once
// Rotation part R of F = R S (det R = +1, S symmetric), the corotational elements' rotation
// (hex8, tet4). For det F > 0 it is the orthogonal polar factor, found by Newton's
// iteration; for inverted, nearly flat or non-finite F it is U V^T of the rotation-variant
// SVD (a reflection in F is left in S; a non-finite F gives R = I).
#include "engine/core/types.hpp"

namespace sinew {

Mat3 polar_rotation(const Mat3& F);

}  // namespace sinew
