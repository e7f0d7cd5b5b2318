#include "engine/materials/eigen_projection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace sinew {

namespace {

// vec(U M V^T), column-major.
Vec9 vec_in_frame(const RotationVariantSvd& svd, const Mat3& M) {
  return vec9(svd.U * M * svd.V.transpose());
}

}  // namespace

Eigenpairs compute_eigenpairs(const SvdEigensystem& system) {
  Eigenpairs pairs;
  const Eigen::SelfAdjointEigenSolver<Mat3> scaling(system.scaling);
  for (int m = 0; m < 3; ++m) {
    pairs.values(m) = scaling.eigenvalues()(m);
    pairs.vectors.col(m) = vec_in_frame(system.svd, Mat3(scaling.eigenvectors().col(m).asDiagonal()));
  }
  const double r = 1 / std::sqrt(2.0);
  for (int k = 0; k < 3; ++k) {
    const int i = k == 0 ? 1 : 0;
    const int j = k == 2 ? 1 : 2;
    Mat3 twist = Mat3::Zero(), flip = Mat3::Zero();
    twist(i, j) = r;
    twist(j, i) = -r;
    flip(i, j) = r;
    flip(j, i) = r;
    pairs.values(3 + k) = system.twist(k);
    pairs.vectors.col(3 + k) = vec_in_frame(system.svd, twist);
    pairs.values(6 + k) = system.flip(k);
    pairs.vectors.col(6 + k) = vec_in_frame(system.svd, flip);
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
  auto remove = [&](double value, const Mat3& Q) {
    const Vec9 q = vec_in_frame(system.svd, Q);
    out.noalias() -= value * q * q.transpose();
  };
  const double r = 1 / std::sqrt(2.0);
  for (int k = 0; k < 3; ++k) {
    if (system.twist(k) >= 0 && system.flip(k) >= 0) continue;
    const int i = k == 0 ? 1 : 0;
    const int j = k == 2 ? 1 : 2;
    Mat3 Q = Mat3::Zero();
    Q(i, j) = r;
    if (system.twist(k) < 0) {
      Q(j, i) = -r;
      remove(system.twist(k), Q);
    }
    if (system.flip(k) < 0) {
      Q(j, i) = r;
      remove(system.flip(k), Q);
    }
  }
  // The scaling block is PSD when its LDL^T has no negative pivot; only then skip its modes.
  const Eigen::LDLT<Mat3> ldlt(system.scaling);
  if (ldlt.info() != Eigen::Success || (ldlt.vectorD().array() < 0).any()) {
    const Eigen::SelfAdjointEigenSolver<Mat3> scaling(system.scaling);
    for (int m = 0; m < 3; ++m)
      if (scaling.eigenvalues()(m) < 0)
        remove(scaling.eigenvalues()(m), Mat3(scaling.eigenvectors().col(m).asDiagonal()));
  }
  return out;
}

Mat9 project_numerically(const Mat9& H) {
  const Eigen::SelfAdjointEigenSolver<Mat9> eig(0.5 * (H + H.transpose()));
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

}  // namespace sinew
