#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "engine/fem/hex8.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

const double kCell = 0.1;

std::array<Vec3, 8> rest_nodes() {
  std::array<Vec3, 8> X;
  for (int n = 0; n < 8; ++n) X[n] = Vec3(0.3, -0.2, 1.0) + (hex8_natural_node(n) + Vec3::Ones()) * kCell / 2;
  return X;
}

Hex8Reference reference() {
  return compute_hex8_reference(kCell, IsotropicElasticity::from_young_poisson(1e5, 0.3));
}

Mat3 some_rotation() {
  return Eigen::AngleAxisd(0.9, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
}

// Corotational energy with R frozen: W(x) = 1/2 (R^T x - X)^T Ke (R^T x - X).
double frozen_energy(const Hex8Reference& ref, const Mat3& R, const std::array<Vec3, 8>& x,
                     const std::array<Vec3, 8>& X) {
  const Vec24 u = hex8_corotated_displacement(R, x, X);
  return 0.5 * u.dot(ref.Ke * u);
}

}  // namespace

TEST_CASE("shape functions: partition of unity and nodal interpolation") {
  for (int n = 0; n < 8; ++n) {
    const auto N = hex8_shape(hex8_natural_node(n));
    for (int m = 0; m < 8; ++m) CHECK(N[m] == doctest::Approx(n == m ? 1.0 : 0.0));
  }
  const auto N = hex8_shape(Vec3(0.2, -0.7, 0.4));
  double sum = 0;
  for (double w : N) sum += w;
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-14));
  // Derivatives of a partition of unity sum to zero.
  CHECK(hex8_shape_derivatives(Vec3(0.2, -0.7, 0.4)).colwise().sum().norm() < 1e-14);
}

TEST_CASE("Ke is symmetric positive semi-definite with exactly six rigid modes") {
  const Hex8Reference ref = reference();
  CHECK((ref.Ke - ref.Ke.transpose()).norm() < 1e-12 * ref.Ke.norm());
  const test::SymmetricEigen eig = test::symmetric_eigen(ref.Ke);
  const auto& values = eig.values;
  const double largest = values.maxCoeff();
  int zeros = 0;
  for (int i = 0; i < 24; ++i) {
    CHECK(values[i] > -1e-10 * largest);
    if (std::abs(values[i]) < 1e-10 * largest) ++zeros;
  }
  CHECK(zeros == 6);
  // Full 2x2x2 integration has no hourglass modes: the seventh eigenvalue is clearly positive.
  CHECK(values[6] > 1e-3 * largest);
}

TEST_CASE("zero force at rest and under a rigid rotation and translation") {
  const Hex8Reference ref = reference();
  const auto X = rest_nodes();
  CHECK(compute_hex8_rotation(X, kCell).isIdentity(1e-12));
  const Mat3 Q = some_rotation();
  std::array<Vec3, 8> x;
  for (int n = 0; n < 8; ++n) x[n] = Q * X[n] + Vec3(4, -1, 2);
  const Mat3 R = compute_hex8_rotation(x, kCell);
  CHECK((R - Q).norm() < 1e-12);
  const Vec24 u = hex8_corotated_displacement(R, x, X);
  const Vec24 f = hex8_elastic_force(ref, R, u);
  CHECK(f.norm() < 1e-9 * ref.Ke.norm() * kCell);
  CHECK(hex8_limit_energy(ref, u) < 1e-20);
}

TEST_CASE("patch test: a linear displacement field gives uniform strain and the exact energy") {
  const Hex8Reference ref = reference();
  const auto X = rest_nodes();
  Mat3 G;  // displacement gradient, deliberately non-symmetric
  G << 1e-3, 2e-3, -1e-3, 0.5e-3, -2e-3, 3e-3, 1e-3, 0, 1.5e-3;
  Vec24 u;
  for (int n = 0; n < 8; ++n) u.segment<3>(3 * n) = G * X[n];
  const Mat3 eps = 0.5 * (G + G.transpose());
  Eigen::Matrix<double, 6, 1> voigt;
  voigt << eps(0, 0), eps(1, 1), eps(2, 2), 2 * eps(0, 1), 2 * eps(1, 2), 2 * eps(2, 0);
  for (int q = 0; q < 8; ++q) CHECK((ref.B[q] * u - voigt).norm() < 1e-12 * voigt.norm());
  // Stored energy 1/2 eps:C:eps V, and paper 000's Ue = sigma:eps V (eq. 13) is twice it.
  const double volume = std::pow(kCell, 3);
  const double exact = 0.5 * voigt.dot(ref.elasticity.voigt_matrix() * voigt) * volume;
  CHECK(0.5 * u.dot(ref.Ke * u) == doctest::Approx(exact).epsilon(1e-12));
  CHECK(hex8_limit_energy(ref, u) == doctest::Approx(2 * exact).epsilon(1e-12));
}

TEST_CASE("elastic force is minus the finite-difference gradient of the energy with R frozen") {
  const Hex8Reference ref = reference();
  const auto X = rest_nodes();
  std::array<Vec3, 8> x;
  const Mat3 Q = some_rotation();
  for (int n = 0; n < 8; ++n)
    x[n] = Q * X[n] + 0.02 * Vec3(std::sin(3.0 * n), std::cos(5.0 * n), std::sin(7.0 * n + 1));
  const Mat3 R = compute_hex8_rotation(x, kCell);
  const Vec24 f = hex8_elastic_force(ref, R, hex8_corotated_displacement(R, x, X));
  for (double step : {1e-3, 1e-4, 1e-5}) {
    Vec24 fd;
    for (int i = 0; i < 24; ++i) {
      auto xp = x, xm = x;
      xp[i / 3][i % 3] += step;
      xm[i / 3][i % 3] -= step;
      fd[i] = -(frozen_energy(ref, R, xp, X) - frozen_energy(ref, R, xm, X)) / (2 * step);
    }
    const double error = (fd - f).norm() / f.norm();
    MESSAGE("FD step " << step << ": relative error " << error);
    // The energy is quadratic in x, so central differences are exact up to rounding:
    // the error is rounding (~1e-16 * |W| / step), far below 1e-6.
    CHECK(error < 1e-6);
  }
  // The warped stiffness is the Jacobian of f with R frozen: check one column by FD.
  Mat24 K;
  hex8_warped_stiffness(ref, R, K);
  for (int i : {0, 7, 23}) {
    auto xp = x;
    xp[i / 3][i % 3] += 1e-6;
    const Vec24 fp = hex8_elastic_force(ref, R, hex8_corotated_displacement(R, xp, X));
    CHECK(((fp - f) / 1e-6 + K.col(i)).norm() < 1e-6 * K.col(i).norm());
  }
}

TEST_CASE("polar rotation is a proper rotation even for inverted and degenerate F") {
  Mat3 inverted = some_rotation();
  inverted.col(1) *= -0.5;
  Mat3 flat = some_rotation();
  flat.col(2).setZero();
  for (const Mat3& F : {inverted, flat, Mat3::Zero().eval()}) {
    const Mat3 R = polar_rotation(F);
    CHECK(R.allFinite());
    CHECK((R.transpose() * R - Mat3::Identity()).norm() < 1e-12);
    CHECK(R.determinant() == doctest::Approx(1.0));
  }
}

TEST_CASE("polar rotation of an inverted F: a proper rotation and a symmetric stretch with one negative value") {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  int inverted = 0;
  for (int i = 0; i < 200; ++i) {
    Mat3 F = Vec3(1, 1, -1).asDiagonal();  // a reflection, perturbed and rotated
    for (int k = 0; k < 9; ++k) F(k) += u(rng);
    F = some_rotation() * F;
    if (F.determinant() >= -0.05) continue;
    ++inverted;
    const Mat3 R = polar_rotation(F);
    CHECK(R.determinant() == doctest::Approx(1.0).epsilon(1e-12));
    const Mat3 S = R.transpose() * F;
    CHECK((S - S.transpose()).norm() <= 1e-13 * F.norm());
    const VecX values = test::symmetric_eigenvalues(0.5 * (S + S.transpose()));  // ascending
    CHECK(values(0) < 0);  // the reflection, along the axis of the smallest stretch
    CHECK(values(1) > 0);
    CHECK(std::abs(values(0)) <= values(1));
  }
  CHECK(inverted > 100);
}

TEST_CASE("polar rotation leaves a symmetric positive-definite stretch F = R S") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (int i = 0; i < 200; ++i) {
    Mat3 F = Mat3::Identity();
    for (int k = 0; k < 9; ++k) F(k) += u(rng);
    F = some_rotation() * F;
    if (F.determinant() <= 0.05) continue;
    const Mat3 S = polar_rotation(F).transpose() * F;
    CHECK((S - S.transpose()).norm() <= 1e-13 * F.norm());
    CHECK(S.determinant() > 0);
    CHECK(S.trace() > 0);
    CHECK((S.block<2, 2>(0, 0)).determinant() > 0);  // leading minors: S positive definite
    CHECK(S(0, 0) > 0);
  }
}
