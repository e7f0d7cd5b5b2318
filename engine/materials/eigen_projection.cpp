#include "engine/materials/eigen_projection.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace sinew {

namespace {

// vec(U M V^T), column-major.
Vec9 vec_in_frame(const RotationVariantSvd& svd, const Mat3& M) {
  return vec9(svd.U * M * svd.V.transpose());
}

// The twist (sign -1) or flip (+1) mode about axis k, vec(U (e_i e_j^T + sign e_j e_i^T) V^T)
// / sqrt 2 with (i, j) the other two axes in order, entry by entry (without the two 3x3
// products of vec_in_frame).
Vec9 pair_mode(const RotationVariantSvd& svd, int k, double sign) {
  const int i = k == 0 ? 1 : 0;
  const int j = k == 2 ? 1 : 2;
  const double r = 1 / std::sqrt(2.0);
  Vec9 q;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a)
      q(3 * b + a) = r * (svd.U(a, i) * svd.V(b, j) + sign * svd.U(a, j) * svd.V(b, i));
  return q;
}

// Sylvester's criterion: all leading minors positive.
bool positive_definite(const Mat3& A) {
  const double minor2 = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0);
  return A(0, 0) > 0 && minor2 > 0 && A.determinant() > 0;
}

}  // namespace

Eigenpairs compute_eigenpairs(const SvdEigensystem& system) {
  Eigenpairs pairs;
  const Eigen::SelfAdjointEigenSolver<Mat3> scaling(system.scaling);
  for (int m = 0; m < 3; ++m) {
    pairs.values(m) = scaling.eigenvalues()(m);
    pairs.vectors.col(m) = vec_in_frame(system.svd, Mat3(scaling.eigenvectors().col(m).asDiagonal()));
  }
  for (int k = 0; k < 3; ++k) {
    pairs.values(3 + k) = system.twist(k);
    pairs.vectors.col(3 + k) = pair_mode(system.svd, k, -1);
    pairs.values(6 + k) = system.flip(k);
    pairs.vectors.col(6 + k) = pair_mode(system.svd, k, 1);
  }
  return pairs;
}

Mat9 assemble_eigensystem(const SvdEigensystem& system, bool clamp) {
  const Eigenpairs pairs = compute_eigenpairs(system);
  const Vec9 values = clamp ? Vec9(pairs.values.cwiseMax(0.0)) : pairs.values;
  return pairs.vectors * values.asDiagonal() * pairs.vectors.transpose();
}

Mat9 remove_negative_modes(const Mat9& H, const SvdEigensystem& system) {
  Mat9 out = H;
  auto remove = [&](double value, const Vec9& q) { out.noalias() -= value * q * q.transpose(); };
  for (int k = 0; k < 3; ++k) {
    if (system.twist(k) < 0) remove(system.twist(k), pair_mode(system.svd, k, -1));
    if (system.flip(k) < 0) remove(system.flip(k), pair_mode(system.svd, k, 1));
  }
  // A positive definite scaling block has no negative mode; otherwise its eigenvalues decide.
  if (!positive_definite(system.scaling)) {
    const Eigen::SelfAdjointEigenSolver<Mat3> scaling(system.scaling);
    for (int m = 0; m < 3; ++m)
      if (scaling.eigenvalues()(m) < 0)
        remove(scaling.eigenvalues()(m), vec_in_frame(system.svd, Mat3(scaling.eigenvectors().col(m).asDiagonal())));
  }
  return out;
}

Mat9 project_numerically(const Mat9& H) {
  const Eigen::SelfAdjointEigenSolver<Mat9> eig(0.5 * (H + H.transpose()));
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

}  // namespace sinew
