#pragma once
// Preconditioned conjugate gradients on the step's symmetric system (both triangles stored),
// its products through the caller's multiply (system_product.hpp's: in parallel, the same bits
// for any thread count).
// One loop for the two preconditioners sinew uses: the diagonal (solver.linear "pcg",
// jacobi_cg.cpp) and an older factorisation (Newton's directions,
// LinearSolver::solve_preconditioned); each brings its own start and stopping rule.
#include "engine/solve/system_product.hpp"

namespace sinew {

enum class CgEnd { Converged, Cap, NoCurvature };

// From x, with r = b - A x given (and not converged): CG iterations until `converged(r)`
// after an update, `max_iterations` updates, or no positive curvature along a direction (or
// r.z <= 0: an indefinite preconditioner). `multiply(p, q)` sets q = A p;
// `precondition(r, z)` sets z = M^-1 r. z, p, q are
// work vectors (kept by the caller: no allocation once they have the size). `iterations`
// receives the updates made.
template <class Multiply, class Precondition, class Converged>
CgEnd conjugate_gradients(const Multiply& multiply, VecX& x, VecX& r, VecX& z, VecX& p, VecX& q, int max_iterations,
                          const Precondition& precondition, const Converged& converged, int& iterations) {
  iterations = 0;
  precondition(r, z);
  p = z;
  double rz = r.dot(z);
  while (iterations < max_iterations) {
    if (!(rz > 0)) return CgEnd::NoCurvature;
    multiply(p, q);
    const double curvature = p.dot(q);
    if (!(curvature > 0)) return CgEnd::NoCurvature;
    const double alpha = rz / curvature;
    x += alpha * p;
    r -= alpha * q;
    ++iterations;
    if (converged(r)) return CgEnd::Converged;
    if (iterations == max_iterations) break;  // no preconditioning for an iteration that will not run
    precondition(r, z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return CgEnd::Cap;
}

}  // namespace sinew
