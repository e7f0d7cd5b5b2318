#include "tests/support/dense_decompositions.hpp"

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

namespace sinew::test {

SymmetricEigen symmetric_eigen(const MatX& A) {
  const Eigen::SelfAdjointEigenSolver<MatX> solver(A);
  return {solver.eigenvalues(), solver.eigenvectors()};
}

VecX symmetric_eigenvalues(const MatX& A) {
  return Eigen::SelfAdjointEigenSolver<MatX>(A, Eigen::EigenvaluesOnly).eigenvalues();
}

double min_eigenvalue(const MatX& A) { return symmetric_eigenvalues(A)(0); }

double max_eigenvalue(const MatX& A) { return symmetric_eigenvalues(A)(A.rows() - 1); }

VecX singular_values(const MatX& A) { return Eigen::JacobiSVD<MatX>(A).singularValues(); }

}  // namespace sinew::test

// The contracts the checks rely on (order, orthonormality, A V = V D), on a symmetric matrix
// with a known spectrum: Q diag(-3, ..., 6) Q^T. Both solvers are backward stable, so the
// errors are a few n eps |A| (~1e-14 here); 1e-12 is a margin for n = 10.
TEST_CASE("test support: symmetric eigen and singular values in the promised order") {
  using namespace sinew;
  const int n = 10;
  const MatX Q = Eigen::HouseholderQR<MatX>(MatX::Random(n, n)).householderQ();
  VecX spectrum(n);
  for (int i = 0; i < n; ++i) spectrum(i) = i - 3.0;
  const MatX A = Q * spectrum.asDiagonal() * Q.transpose();
  const test::SymmetricEigen eigen = test::symmetric_eigen(A);
  CHECK((eigen.values - spectrum).cwiseAbs().maxCoeff() < 1e-12 * 6);
  CHECK((eigen.vectors.transpose() * eigen.vectors - MatX::Identity(n, n)).norm() < 1e-12);
  CHECK((A * eigen.vectors - eigen.vectors * eigen.values.asDiagonal()).norm() < 1e-12 * 6);
  CHECK((test::symmetric_eigenvalues(A) - spectrum).cwiseAbs().maxCoeff() < 1e-12 * 6);
  CHECK(test::min_eigenvalue(A) == doctest::Approx(-3).epsilon(1e-12));
  CHECK(test::max_eigenvalue(A) == doctest::Approx(6).epsilon(1e-12));
  // Singular values of A: |spectrum| sorted descending: 6 5 4 3 3 2 2 1 1 0.
  const VecX sigma = test::singular_values(A);
  const double expected[] = {6, 5, 4, 3, 3, 2, 2, 1, 1, 0};
  for (int i = 0; i < n; ++i) CHECK(std::abs(sigma(i) - expected[i]) < 1e-12 * 6);
}
