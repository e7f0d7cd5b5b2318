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

// out = A x for an A with the system pattern's node blocks (system_pattern.hpp: columns 3j,
// 3j+1 and 3j+2 hold the same rows, which come in whole nodes 3i, 3i+1, 3i+2), as every step
// matrix has: the three columns of a node are summed together, one index and one load of
// x_i a block of nine entries, three independent chains of additions. Each column's sum
// takes its terms in multiply_system's order: the same bits. Throws std::invalid_argument
// when the columns of a node differ in length or in a multiple of 3, or a block's first row
// lies outside [0, n - 3] (cheap tests, no read outside x); whether the three columns hold
// the same rows, in aligned triples, only the sanitizer build checks (has_node_blocks).
void multiply_node_blocked(const SparseMatrix& A, const Eigen::Ref<const VecX>& x, VecX& out);

// Whether A is compressed, square with 3k columns, and each node's three columns hold the
// same rows in whole nodes (reads every row index).
bool has_node_blocks(const SparseMatrix& A);

// out = A x for an A whose nonzero entries all lie on its diagonal d, stored on a whole
// pattern (a hyperelastic scene's mass matrix): one pass over d, with the bits of
// multiply_system's column sums for a finite x, as those add exact zeros around d_j x_j
// ("+ 0.0" gives the +0 they give where d_j x_j is -0). (An infinite x_i spreads NaN to other
// entries there, 0 * inf, not here.) out must not alias x.
void multiply_diagonal(const VecX& d, const VecX& x, VecX& out);

}  // namespace sinew
