#pragma once
// y = A x for the step's symmetric system matrix, in parallel. A is stored whole (both
// triangles, column-major), so A x = A^T x: entry j is column j's dot product with x, which
// any thread computes in the same order. Eigen's product scatters column by column on one
// thread; SQP takes two or three products per iteration (residual, A d).
#include "engine/assembly/system_pattern.hpp"
#include "engine/core/types.hpp"

namespace sinew {

// out = A x, out resized to A.rows() (no allocation when it has that size already); A
// symmetric with both triangles stored. out must not alias x.
void multiply_system(const SparseMatrix& A, const Eigen::Ref<const VecX>& x, VecX& out);

// out = A x for an A whose nonzero entries all lie on its diagonal d, stored on a whole
// pattern (a hyperelastic scene's mass matrix): one pass over d, with the bits of
// multiply_system's column sums for a finite x, as those add exact zeros around d_j x_j
// ("+ 0.0" gives the +0 they give where d_j x_j is -0). (An infinite x_i spreads NaN to other
// entries there, 0 * inf, not here.) out must not alias x.
void multiply_diagonal(const VecX& d, const VecX& x, VecX& out);

}  // namespace sinew
