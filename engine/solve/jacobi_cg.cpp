#include "engine/solve/jacobi_cg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/solve/conjugate_gradients.hpp"

namespace sinew {

void JacobiCg::compute(const SparseMatrix& A) {
  m_inverse_diagonal.resize(A.rows());
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    const double d = A.coeff(i, i);
    m_inverse_diagonal[i] = d != 0 ? 1 / d : 1.0;
  }
}

JacobiCg::Result JacobiCg::solve(const SparseMatrix& A, const VecX& b, VecX& x, double tolerance, int max_iterations) {
  Result result;
  if (A.rows() != b.size() || A.cols() != b.size() || m_inverse_diagonal.size() != b.size())
    throw std::logic_error("JacobiCg::solve: A, b and the preconditioner (compute) differ in size");
  if (x.size() != b.size()) x.setZero(b.size());
  const double rhs2 = b.squaredNorm();
  if (rhs2 == 0) {
    x.setZero();
    return result;
  }
  // Squared residual norms below this stop (the floor: a tolerance of 0 still ends).
  const double threshold = std::max(tolerance * tolerance * rhs2, std::numeric_limits<double>::min());
  VecX &r = m_residual, &z = m_preconditioned, &p = m_search, &q = m_product;
  // From x = 0 (every column of solve_many, the velocity step) A x is 0: r = b, the same
  // bits (b - (+-0) = b) without a product.
  if (x.isZero(0)) {
    r = b;
  } else {
    multiply_system(A, x, q);
    r = b - q;
  }
  double residual2 = r.squaredNorm();
  if (residual2 >= threshold)
    conjugate_gradients(
        [&](const VecX& in, VecX& out) { multiply_system(A, in, out); }, x, r, z, p, q, max_iterations,
        [&](const VecX& from, VecX& to) { to = m_inverse_diagonal.cwiseProduct(from); },
        [&](const VecX& residual) { return (residual2 = residual.squaredNorm()) < threshold; }, result.iterations);
  result.error = std::sqrt(residual2 / rhs2);
  result.converged = residual2 < threshold;
  return result;
}

}  // namespace sinew
