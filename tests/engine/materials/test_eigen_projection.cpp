#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>

#include "engine/materials/eigen_projection.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

// A made-up system: rotations U, V, a symmetric scaling block with one negative value, and
// twist/flip values of both signs.
SvdEigensystem some_system() {
  SvdEigensystem system;
  system.svd.U = Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
  system.svd.V = Eigen::AngleAxisd(-1.1, Vec3(-0.3, 0.4, 1).normalized()).toRotationMatrix();
  system.svd.S = Vec3(1.3, 0.9, -0.6);
  system.scaling << 4, 1, -2, 1, 3, 0.5, -2, 0.5, -1;
  system.twist = Vec3(2, -3, 0.5);
  system.flip = Vec3(-0.25, 1.5, 6);
  return system;
}

}  // namespace

TEST_CASE("eigenpairs: orthonormal eigenmatrices of the assembled matrix") {
  const SvdEigensystem system = some_system();
  const Eigenpairs pairs = compute_eigenpairs(system);
  const Mat9 H = assemble_eigensystem(system, false);
  // Products of rotations and unit vectors: exact up to round-off (~1e-15).
  CHECK((pairs.vectors.transpose() * pairs.vectors - Mat9::Identity()).norm() < 1e-13);
  for (int m = 0; m < 9; ++m)
    CHECK((H * pairs.vectors.col(m) - pairs.values(m) * pairs.vectors.col(m)).norm() < 1e-13);
  // Twist about axis 2 is U (e0 e1^T - e1 e0^T) V^T / sqrt 2, flip the symmetric one.
  Mat3 twist = Mat3::Zero();
  twist(0, 1) = 1;
  twist(1, 0) = -1;
  const Mat3 expected = system.svd.U * twist * system.svd.V.transpose() / std::sqrt(2.0);
  CHECK((pairs.vectors.col(5) - vec9(expected)).norm() < 1e-14);
  CHECK(pairs.values(5) == system.twist(2));
  CHECK(pairs.values(6) == system.flip(0));
  // The scaling values are those of the 3x3 block.
  Vec3 scaling = pairs.values.head<3>();
  std::sort(scaling.data(), scaling.data() + 3);
  CHECK((scaling - test::symmetric_eigenvalues(system.scaling)).norm() < 1e-13);
}

TEST_CASE("clamped assembly equals the numerical projection and is PSD") {
  const SvdEigensystem system = some_system();
  const Mat9 H = assemble_eigensystem(system, false);
  const Mat9 clamped = assemble_eigensystem(system, true);
  CHECK((clamped - project_numerically(H)).norm() < 1e-12 * H.norm());
  const test::SymmetricEigen eig = test::symmetric_eigen(clamped);
  CHECK(eig.values.minCoeff() > -1e-13);
  // Three values were negative (one of the scaling block's: its determinant is -26 and its
  // trace 6; twist 1; flip 0): rank 6 after clamping.
  int positive = 0;
  for (int m = 0; m < 9; ++m) positive += eig.values(m) > 1e-12;
  CHECK(positive == 6);
}

TEST_CASE("numerical projection leaves a PSD matrix alone") {
  Mat9 A;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) A(i, j) = std::sin(1.0 + i * 9 + j);
  const Mat9 psd = A * A.transpose();
  CHECK((project_numerically(psd) - psd).norm() < 1e-12 * psd.norm());
}
