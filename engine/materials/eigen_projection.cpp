#include "engine/materials/eigen_projection.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace sinew {

namespace {

// U M V^T, and its vec (column-major).
Mat3 in_frame(const RotationVariantSvd& svd, const Mat3& M) { return svd.U * M * svd.V.transpose(); }
Vec9 vec_in_frame(const RotationVariantSvd& svd, const Mat3& M) { return vec9(in_frame(svd, M)); }

// The twist (sign -1) or flip (+1) eigenmatrix about axis k, U (e_i e_j^T + sign e_j e_i^T)
// V^T / sqrt 2 with (i, j) the other two axes in order, entry by entry (without the two 3x3
// products of U M V^T).
Mat3 pair_mode(const RotationVariantSvd& svd, int k, double sign) {
  const int i = k == 0 ? 1 : 0;
  const int j = k == 2 ? 1 : 2;
  const double r = 1 / std::sqrt(2.0);
  Mat3 Q;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) Q(a, b) = r * (svd.U(a, i) * svd.V(b, j) + sign * svd.U(a, j) * svd.V(b, i));
  return Q;
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
    pairs.vectors.col(3 + k) = vec9(pair_mode(system.svd, k, -1));
    pairs.values(6 + k) = system.flip(k);
    pairs.vectors.col(6 + k) = vec9(pair_mode(system.svd, k, 1));
  }
  return pairs;
}

Mat9 assemble_eigensystem(const SvdEigensystem& system, bool clamp) {
  const Eigenpairs pairs = compute_eigenpairs(system);
  const Vec9 values = clamp ? Vec9(pairs.values.cwiseMax(0.0)) : pairs.values;
  return pairs.vectors * values.asDiagonal() * pairs.vectors.transpose();
}

int negative_modes(const SvdEigensystem& system, NegativeModes& modes) {
  int count = 0;
  auto add = [&](double value, const Mat3& Q) {
    modes.values[count] = value;
    modes.matrices[count++] = Q;
  };
  for (int k = 0; k < 3; ++k) {
    if (system.twist(k) < 0) add(system.twist(k), pair_mode(system.svd, k, -1));
    if (system.flip(k) < 0) add(system.flip(k), pair_mode(system.svd, k, 1));
  }
  // A positive definite scaling block has no negative mode; otherwise its eigenvalues decide.
  if (!positive_definite(system.scaling)) {
    const Eigen::SelfAdjointEigenSolver<Mat3> scaling(system.scaling);
    for (int m = 0; m < 3; ++m)
      if (scaling.eigenvalues()(m) < 0)
        add(scaling.eigenvalues()(m), in_frame(system.svd, Mat3(scaling.eigenvectors().col(m).asDiagonal())));
  }
  return count;
}

Mat9 remove_negative_modes(const Mat9& H, const SvdEigensystem& system) {
  Mat9 out = H;
  NegativeModes modes;
  const int count = negative_modes(system, modes);
  for (int m = 0; m < count; ++m) {
    const Vec9 q = vec9(modes.matrices[m]);
    out.noalias() -= modes.values[m] * q * q.transpose();
  }
  return out;
}

Mat9 project_numerically(const Mat9& H) {
  const Eigen::SelfAdjointEigenSolver<Mat9> eig(0.5 * (H + H.transpose()));
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

}  // namespace sinew
