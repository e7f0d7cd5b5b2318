#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "engine/fem/hex8.hpp"
#include "engine/fem/tet4.hpp"
#include "engine/geometry/lattice_tets.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

const IsotropicElasticity kMaterial = IsotropicElasticity::from_young_poisson(1e5, 0.3);

// A skewed, positively oriented rest tet (not axis-aligned, not regular).
std::array<Vec3, 4> rest_nodes() {
  return {Vec3(0.3, -0.2, 1.0), Vec3(0.42, -0.17, 1.01), Vec3(0.33, -0.08, 0.98),
          Vec3(0.35, -0.15, 1.13)};
}

Mat3 some_rotation() {
  return Eigen::AngleAxisd(0.9, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
}

// Corotational energy with R frozen: W(x) = 1/2 (R^T x - X)^T Ke (R^T x - X).
double frozen_energy(const Tet4Reference& ref, const Mat3& R, const std::array<Vec3, 4>& x,
                     const std::array<Vec3, 4>& X) {
  const Vec12 u = tet4_corotated_displacement(R, x, X);
  return 0.5 * u.dot(ref.Ke * u);
}

Eigen::Matrix<double, 6, 1> voigt_strain(const Mat3& G) {
  const Mat3 eps = 0.5 * (G + G.transpose());
  Eigen::Matrix<double, 6, 1> v;
  v << eps(0, 0), eps(1, 1), eps(2, 2), 2 * eps(0, 1), 2 * eps(1, 2), 2 * eps(2, 0);
  return v;
}

Mat3 displacement_gradient() {  // deliberately non-symmetric
  Mat3 G;
  G << 1e-3, 2e-3, -1e-3, 0.5e-3, -2e-3, 3e-3, 1e-3, 0, 1.5e-3;
  return G;
}

}  // namespace

TEST_CASE("tet4: reference volume, shape gradients and F") {
  const auto X = rest_nodes();
  const Tet4Reference ref = compute_tet4_reference(X, kMaterial);
  CHECK(ref.volume == doctest::Approx(tet_signed_volume(X[0], X[1], X[2], X[3])));
  CHECK(ref.volume > 0);
  // Gradients of a partition of unity sum to zero; sum_n X_n grad N_n^T = I.
  CHECK(ref.dN_dX.colwise().sum().norm() < 1e-12);
  Mat3 I = Mat3::Zero();
  for (int n = 0; n < 4; ++n) I += X[n] * ref.dN_dX.row(n);
  CHECK((I - Mat3::Identity()).norm() < 1e-12);
  CHECK((tet4_deformation_gradient(ref, X) - Mat3::Identity()).norm() < 1e-12);
  // An affine map x = A X + t has F = A.
  Mat3 A = Mat3::Identity() + displacement_gradient() * 100;
  std::array<Vec3, 4> x;
  for (int n = 0; n < 4; ++n) x[n] = A * X[n] + Vec3(1, 2, 3);
  CHECK((tet4_deformation_gradient(ref, x) - A).norm() < 1e-12);
}

TEST_CASE("tet4: degenerate and inverted rest tets are rejected") {
  auto X = rest_nodes();
  std::swap(X[2], X[3]);
  CHECK_THROWS_AS(compute_tet4_reference(X, kMaterial), std::invalid_argument);
  X = rest_nodes();
  X[3] = X[0] + 0.3 * (X[1] - X[0]) + 0.6 * (X[2] - X[0]);  // flat
  CHECK_THROWS_AS(compute_tet4_reference(X, kMaterial), std::invalid_argument);
  X[3] = X[1];  // repeated node
  CHECK_THROWS_AS(compute_tet4_reference(X, kMaterial), std::invalid_argument);
}

TEST_CASE("tet4: Ke is symmetric positive semi-definite with exactly six rigid modes") {
  const Tet4Reference ref = compute_tet4_reference(rest_nodes(), kMaterial);
  CHECK((ref.Ke - ref.Ke.transpose()).norm() < 1e-12 * ref.Ke.norm());
  const test::SymmetricEigen eig = test::symmetric_eigen(ref.Ke);
  const auto& values = eig.values;
  const double largest = values.maxCoeff();
  int zeros = 0;
  for (int i = 0; i < 12; ++i) {
    CHECK(values[i] > -1e-10 * largest);
    if (std::abs(values[i]) < 1e-10 * largest) ++zeros;
  }
  CHECK(zeros == 6);
  CHECK(values[6] > 1e-3 * largest);
}

TEST_CASE("tet4: zero force at rest and under a rigid rotation and translation") {
  const auto X = rest_nodes();
  const Tet4Reference ref = compute_tet4_reference(X, kMaterial);
  CHECK(compute_tet4_rotation(ref, X).isIdentity(1e-12));
  const Mat3 Q = some_rotation();
  std::array<Vec3, 4> x;
  for (int n = 0; n < 4; ++n) x[n] = Q * X[n] + Vec3(4, -1, 2);
  const Mat3 R = compute_tet4_rotation(ref, x);
  CHECK((R - Q).norm() < 1e-12);
  const Vec12 u = tet4_corotated_displacement(R, x, X);
  const Vec12 f = tet4_elastic_force(ref, R, u);
  CHECK(f.norm() < 1e-9 * ref.Ke.norm() * 0.1);
  CHECK(tet4_limit_energy(ref, u) < 1e-20);
}

TEST_CASE("tet4: patch test on one tet: constant strain, f = -V B^T C eps, exact energy") {
  const auto X = rest_nodes();
  const Tet4Reference ref = compute_tet4_reference(X, kMaterial);
  const Mat3 G = displacement_gradient();
  Vec12 u;
  for (int n = 0; n < 4; ++n)
    u.segment<3>(3 * n) = G * X[n] + Vec3(0.1, 0.2, 0.3);  // plus a translation
  const Eigen::Matrix<double, 6, 1> eps = voigt_strain(G);
  const Mat6x12 B = tet4_strain_displacement(ref);
  CHECK((B * u - eps).norm() < 1e-12 * eps.norm());
  const Eigen::Matrix<double, 6, 6> C = ref.elasticity.voigt_matrix();
  const Vec12 expected = -ref.volume * B.transpose() * C * eps;
  const Vec12 f = tet4_elastic_force(ref, Mat3::Identity(), u);
  CHECK((f - expected).norm() < 1e-12 * expected.norm());
  // Stored energy 1/2 eps:C:eps V; paper 000's Ue (eq. 13) is twice it.
  const double exact = 0.5 * eps.dot(C * eps) * ref.volume;
  CHECK(0.5 * u.dot(ref.Ke * u) == doctest::Approx(exact).epsilon(1e-12));
  CHECK(tet4_limit_energy(ref, u) == doctest::Approx(2 * exact).epsilon(1e-12));
}

TEST_CASE("tet4: patch test on a mesh: a linear field leaves interior nodes in equilibrium") {
  // 2x2x2 cells split into 48 tets: the centre node (1,1,1) h is interior.
  const HexLattice lat = make_box_lattice(Vec3(0.1, -0.3, 0.2), 0.2, 2, 2, 2);
  const LatticeTets lt = split_lattice_into_tets(lat);
  const Mat3 G = displacement_gradient();
  VecX force = VecX::Zero(3 * lt.mesh.nodes.size());
  for (const auto& tet : lt.mesh.tets) {
    std::array<Vec3, 4> X;
    Vec12 u;
    for (int k = 0; k < 4; ++k) {
      X[k] = lt.mesh.nodes[tet[k]];
      u.segment<3>(3 * k) = G * X[k];
    }
    const Vec12 f = tet4_elastic_force(compute_tet4_reference(X, kMaterial), Mat3::Identity(), u);
    for (int k = 0; k < 4; ++k) force.segment<3>(3 * tet[k]) += f.segment<3>(3 * k);
  }
  const Vec3 centre = lat.origin + Vec3::Constant(0.2);
  int interior = 0;
  double scale = 0;
  for (std::size_t n = 0; n < lt.mesh.nodes.size(); ++n)
    scale = std::max(scale, force.segment<3>(3 * n).norm());
  for (std::size_t n = 0; n < lt.mesh.nodes.size(); ++n)
    if ((lt.mesh.nodes[n] - centre).norm() < 1e-12) {
      ++interior;
      CHECK(force.segment<3>(3 * n).norm() < 1e-12 * scale);
    }
  CHECK(interior == 1);
  CHECK(scale > 0);
}

TEST_CASE(
    "tet4: elastic force is minus the finite-difference gradient of the energy with R frozen") {
  const auto X = rest_nodes();
  const Tet4Reference ref = compute_tet4_reference(X, kMaterial);
  std::array<Vec3, 4> x;
  const Mat3 Q = some_rotation();
  for (int n = 0; n < 4; ++n)
    x[n] = Q * X[n] + 0.02 * Vec3(std::sin(3.0 * n), std::cos(5.0 * n), std::sin(7.0 * n + 1));
  const Mat3 R = compute_tet4_rotation(ref, x);
  const Vec12 f = tet4_elastic_force(ref, R, tet4_corotated_displacement(R, x, X));
  for (double step : {1e-3, 1e-4, 1e-5}) {
    Vec12 fd;
    for (int i = 0; i < 12; ++i) {
      auto xp = x, xm = x;
      xp[i / 3][i % 3] += step;
      xm[i / 3][i % 3] -= step;
      fd[i] = -(frozen_energy(ref, R, xp, X) - frozen_energy(ref, R, xm, X)) / (2 * step);
    }
    const double error = (fd - f).norm() / f.norm();
    MESSAGE("FD step " << step << ": relative error " << error);
    // The energy is quadratic in x: central differences are exact up to rounding.
    CHECK(error < 1e-6);
  }
  // The warped stiffness is the Jacobian of f with R frozen: check columns by FD.
  Mat12 K;
  tet4_warped_stiffness(ref, R, K);
  CHECK((K - K.transpose()).norm() < 1e-12 * K.norm());
  for (int i : {0, 5, 11}) {
    auto xp = x;
    xp[i / 3][i % 3] += 1e-6;
    const Vec12 fp = tet4_elastic_force(ref, R, tet4_corotated_displacement(R, xp, X));
    CHECK(((fp - f) / 1e-6 + K.col(i)).norm() < 1e-6 * K.col(i).norm());
  }
}

TEST_CASE("tet4 vs hex8: the same box under the same uniform strain has the same energy") {
  // Uniform strain is reproduced exactly by both elements, so the energies agree to rounding.
  const double h = 0.1;
  const HexLattice lat = make_box_lattice(Vec3(0.3, -0.2, 1.0), h, 3, 2, 2);
  const LatticeTets lt = split_lattice_into_tets(lat);
  Mat3 G = Mat3::Zero();
  G.diagonal() << 0.02, -0.005, 0.01;  // a uniform stretch
  G(0, 1) = 0.004;                     // and a little shear
  const Hex8Reference hex = compute_hex8_reference(h, kMaterial);
  double hex_energy = 0, tet_energy = 0;
  for (const auto& cell : lat.cells) {
    Vec24 u;
    for (int n = 0; n < 8; ++n) u.segment<3>(3 * n) = G * lat.nodes[cell[n]];
    hex_energy += hex8_limit_energy(hex, u);
  }
  for (const auto& tet : lt.mesh.tets) {
    std::array<Vec3, 4> X;
    Vec12 u;
    for (int k = 0; k < 4; ++k) {
      X[k] = lt.mesh.nodes[tet[k]];
      u.segment<3>(3 * k) = G * X[k];
    }
    tet_energy += tet4_limit_energy(compute_tet4_reference(X, kMaterial), u);
  }
  const Eigen::Matrix<double, 6, 1> eps = voigt_strain(G);
  const double exact =
      eps.dot(kMaterial.voigt_matrix() * eps) * 12 * h * h * h;  // Ue = sigma:eps V
  CHECK(hex_energy == doctest::Approx(exact).epsilon(1e-12));
  CHECK(tet_energy == doctest::Approx(exact).epsilon(1e-12));
  // Under the same uniform stretch, rotated: the corotated energies still agree.
  const Mat3 Q = some_rotation();
  double tet_rotated = 0;
  for (const auto& tet : lt.mesh.tets) {
    std::array<Vec3, 4> X, x;
    for (int k = 0; k < 4; ++k) {
      X[k] = lt.mesh.nodes[tet[k]];
      x[k] = Q * (Mat3::Identity() + 0.5 * (G + G.transpose())) * X[k];
    }
    const Tet4Reference ref = compute_tet4_reference(X, kMaterial);
    const Mat3 R = compute_tet4_rotation(ref, x);
    tet_rotated += tet4_limit_energy(ref, tet4_corotated_displacement(R, x, X));
  }
  CHECK(tet_rotated == doctest::Approx(exact).epsilon(1e-9));
}
