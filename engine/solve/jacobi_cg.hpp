#pragma once
// Conjugate gradients preconditioned with the diagonal (Jacobi), for solver.linear "pcg":
// the same iteration as Eigen's ConjugateGradient with its DiagonalPreconditioner, but its
// products with A through multiply_system (in parallel, each entry summed by one task:
// the same bits for any thread count) and its vectors kept between solves, so that a warm
// step allocates nothing (Eigen's allocated four vectors a solve, and a temporary for x).
#include "engine/assembly/system_pattern.hpp"
#include "engine/core/types.hpp"

namespace sinew {

class JacobiCg {
 public:
  struct Result {
    int iterations = 0;       // products with A taken
    double error = 0;         // |b - A x| / |b| at the end (0 for b = 0)
    bool converged = true;    // error below the tolerance
  };
  // The preconditioner: 1 / A_ii (1 where A_ii is 0). A symmetric, both triangles stored.
  void compute(const SparseMatrix& A);
  // A x = b from the x passed in (resized to zero if its size is not b's), until
  // |b - A x| < tolerance |b| or max_iterations; b = 0 gives x = 0. Stops unconverged, x as
  // it was then, if a search direction shows no positive curvature (A not SPD) or the
  // preconditioned residual no positive product (a negative diagonal). Throws
  // std::logic_error if A, b and compute()'s matrix differ in size. Not for two threads at
  // once: it works in the object's vectors.
  Result solve(const SparseMatrix& A, const VecX& b, VecX& x, double tolerance, int max_iterations);

 private:
  VecX m_inverse_diagonal, m_residual, m_preconditioned, m_search, m_product;
};

}  // namespace sinew
