#pragma once
// Checks shared by the material tests (one test file per material): finite-difference
// derivatives with a shrinking step, the closed-form eigensystem against Eigen's solver, the
// projection, Hooke's law at small strain, finiteness on inverted and degenerate F.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/materials/isotropic_material.hpp"
#include "engine/materials/material.hpp"
#include "tests/support/dense_decompositions.hpp"

namespace sinew::material_checks {

inline MaterialParameters parameters(double poisson = 0.3) {
  MaterialParameters p;
  p.young = 1e5;
  p.poisson = poisson;
  return p;
}

// U diag(s) V^T with two fixed, unrelated rotations, so F has no special alignment.
inline Mat3 with_singular_values(const Vec3& s) {
  const Mat3 U = Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
  const Mat3 V = Eigen::AngleAxisd(-1.1, Vec3(-0.3, 0.4, 1).normalized()).toRotationMatrix();
  return U * s.asDiagonal() * V.transpose();
}

struct Sample {
  std::string name;
  Mat3 F;
};

// Singular values kept apart (and sigma_i + sigma_j away from 0) so that finite differences
// at steps down to 1e-4 are in their asymptotic regime.
inline std::vector<Sample> samples(bool include_inverted = true) {
  std::vector<Sample> out = {
      {"general", with_singular_values(Vec3(1.3, 0.9, 0.75))},
      {"large", with_singular_values(Vec3(2.0, 1.4, 0.5))},
      {"compressed", with_singular_values(Vec3(0.6, 0.5, 0.3))},
  };
  if (include_inverted) out.push_back({"inverted", with_singular_values(Vec3(1.3, 0.9, -0.6))});
  return out;
}

// Near rest, slightly expanded with every sigma > 1: the Hessian is PD for every material here
// (at F = I it is Hooke's, PD for -1 < nu < 1/2; all sigma > 1 keeps ARAP's twists
// 2 mu - 4 mu / (sigma_i + sigma_j) positive; J - 1 = 0.06 keeps the flips of the J-materials,
// which turn negative under larger expansion, positive).
inline Mat3 near_rest() { return with_singular_values(Vec3(1.03, 1.02, 1.01)); }

// Inverted and degenerate F: J < 0, and F crushed to a plane, a line and a point.
inline std::vector<Sample> degenerate_samples() {
  return {
      {"minus identity", -Mat3::Identity()},
      {"reflection", Vec3(1, 1, -1).asDiagonal()},
      {"inverted", with_singular_values(Vec3(1.3, 0.9, -0.6))},
      {"plane", with_singular_values(Vec3(1.2, 0.8, 0))},
      {"plane aligned", Vec3(1, 1, 0).asDiagonal()},
      {"line", with_singular_values(Vec3(1.5, 0, 0))},
      {"point", Mat3::Zero()},
  };
}

inline Mat3 unit(int a) {
  Mat3 E = Mat3::Zero();
  E(a % 3, a / 3) = 1;
  return E;
}

// Relative error of P against central differences of Psi, one entry per step.
inline std::vector<double> gradient_errors(const Material& m, const Mat3& F,
                                           const std::vector<double>& steps) {
  const Mat3 P = m.pk1(F);
  std::vector<double> errors;
  for (double h : steps) {
    Mat3 fd;
    for (int a = 0; a < 9; ++a)
      fd(a % 3, a / 3) = (m.energy(F + h * unit(a)) - m.energy(F - h * unit(a))) / (2 * h);
    errors.push_back((fd - P).norm() / P.norm());
  }
  return errors;
}

// Relative error of the Hessian against central differences of P.
inline std::vector<double> hessian_errors(const Material& m, const Mat3& F,
                                          const std::vector<double>& steps) {
  const Mat9 H = m.hessian(F);
  std::vector<double> errors;
  for (double h : steps) {
    Mat9 fd;
    for (int a = 0; a < 9; ++a) fd.col(a) = vec9((m.pk1(F + h * unit(a)) - m.pk1(F - h * unit(a))) / (2 * h));
    errors.push_back((fd - H).norm() / H.norm());
  }
  return errors;
}

// Central differences err ~ C h^2 + eps |f| / h: at these steps (1e-2 .. 1e-4, |F| ~ 1) the
// h^2 term dominates, so each 10x smaller step must cut the error ~100x; we ask for 30x (room
// for the h^4 term) while the error is still above the round-off floor (~1e-10 at h = 1e-4),
// and the smallest error must be below 1e-6 (issue 6).
inline void check_shrinking(const std::vector<double>& errors) {
  for (size_t k = 1; k < errors.size(); ++k)
    if (errors[k - 1] > 1e-9) CHECK(errors[k] < errors[k - 1] / 30);
  CHECK(*std::min_element(errors.begin(), errors.end()) < 1e-6);
}

inline void check_derivatives(const Material& m, const std::vector<Sample>& list) {
  const std::vector<double> steps = {1e-2, 1e-3, 1e-4};
  for (const Sample& s : list) {
    INFO(m.name(), " at ", s.name);
    const auto g = gradient_errors(m, s.F, steps);
    INFO("gradient errors ", g[0], " ", g[1], " ", g[2]);
    check_shrinking(g);
    const auto h = hessian_errors(m, s.F, steps);
    INFO("hessian errors ", h[0], " ", h[1], " ", h[2]);
    check_shrinking(h);
  }
}

// Closed-form eigenpairs against Eigen's SelfAdjointEigenSolver on the analytic Hessian.
// Both come from double arithmetic on an SVD accurate to ~1e-15 |F|, so values agree to
// ~1e-14 of the spectrum's scale; 1e-8 (issue 6) leaves a wide margin. Eigenvectors are
// compared as subspaces: each closed-form vector must lie in the span of the numerical vectors
// whose values are within 1e-6 of the scale of its own (Davis-Kahan: angle <= |dH| / gap
// ~ 1e-15 / 1e-6), which handles repeated values (e.g. flip = 2 mu three times).
inline void check_eigensystem(const IsotropicMaterial& m, const Mat3& F) {
  const Mat9 H = m.hessian(F);
  const Eigenpairs pairs = compute_eigenpairs(m.eigensystem(F));
  const test::SymmetricEigen numeric = test::symmetric_eigen(H);
  const double scale = numeric.values.cwiseAbs().maxCoeff();
  REQUIRE(scale > 0);

  CHECK((pairs.vectors.transpose() * pairs.vectors - Mat9::Identity()).norm() < 1e-12);
  Vec9 sorted = pairs.values;
  std::sort(sorted.data(), sorted.data() + 9);
  CHECK((sorted - numeric.values).cwiseAbs().maxCoeff() < 1e-8 * scale);
  for (int m_ = 0; m_ < 9; ++m_) {
    const Vec9 q = pairs.vectors.col(m_);
    CHECK((H * q - pairs.values(m_) * q).norm() < 1e-8 * scale);
    Vec9 projected = Vec9::Zero();
    for (int n = 0; n < 9; ++n)
      if (std::abs(numeric.values(n) - pairs.values(m_)) < 1e-6 * scale)
        projected += numeric.vectors.col(n).dot(q) * numeric.vectors.col(n);
    CHECK(projected.norm() > 1 - 1e-8);
  }
}

// The projected Hessian is PSD and equals the numerical projection of the analytic Hessian
// (the nearest PSD matrix is unique). Round-off of a 9x9 product of unit vectors: ~1e-15
// of the scale, so 1e-10 and 1e-8 are margins, not fitted values.
inline void check_projection(const Material& m, const Mat3& F) {
  const Mat9 H = m.hessian(F);
  const Mat9 projected = m.projected_hessian(F);
  const double scale = H.norm();
  CHECK((projected - projected.transpose()).norm() < 1e-12 * scale);
  const test::SymmetricEigen eig = test::symmetric_eigen(projected);
  CHECK(eig.values.minCoeff() > -1e-10 * scale);
  CHECK((projected - project_numerically(H)).norm() < 1e-8 * scale);
}

// Where the Hessian is PSD, the projection must leave it alone.
inline void check_projection_keeps_psd(const Material& m, const Mat3& F) {
  const Mat9 H = m.hessian(F);
  const test::SymmetricEigen eig = test::symmetric_eigen(H);
  REQUIRE(eig.values.minCoeff() >= 0);  // precondition of this check
  CHECK((m.projected_hessian(F) - H).norm() < 1e-10 * H.norm());
}

inline double stiffness_scale(const MaterialParameters& p) {
  const LameParameters lame = lame_parameters(p);
  return 2 * lame.mu + 3 * std::abs(lame.lambda);
}

// P(I) = 0 and no force under a rigid rotation: the exact value is 0, round-off is ~1e-16 of
// the stiffness, so 1e-12 of it.
inline void check_rest(const Material& m, const MaterialParameters& p) {
  const double tol = 1e-12 * stiffness_scale(p);
  CHECK(m.pk1(Mat3::Identity()).norm() < tol);
  const Mat3 Q = Eigen::AngleAxisd(2.5, Vec3(0.2, -1, 0.6).normalized()).toRotationMatrix();
  CHECK(m.pk1(Q).norm() < tol);
}

// Hooke's law at F = I + eps G: P(I + eps G) = eps (2 mu_L sym(G) + lambda_L tr(G) I) + O(eps^2).
// If the linear term matched, the residual falls 100x when eps falls 10x (a wrong linear term
// would make it fall only 10x): we ask for 50x. At eps = 1e-5 the O(eps^2) residual relative to
// the O(eps) stress is C eps with C a ratio of third to second derivatives (O(10) for these
// materials at nu <= 0.45): below 1e-3.
inline void check_hooke(const Material& m, const MaterialParameters& p, bool with_lambda = true) {
  const LameParameters lame = lame_parameters(p);
  Mat3 G;
  G << 0.3, -0.7, 0.2, 0.5, -0.4, 0.9, -0.1, 0.6, 0.8;
  const Mat3 eps = 0.5 * (G + G.transpose());
  const Mat3 hooke = 2 * lame.mu * eps + (with_lambda ? lame.lambda : 0.0) * eps.trace() * Mat3::Identity();
  std::vector<double> residual;
  for (double e : {1e-3, 1e-4, 1e-5}) residual.push_back((m.pk1(Mat3::Identity() + e * G) - e * hooke).norm());
  INFO(m.name(), " residuals ", residual[0], " ", residual[1], " ", residual[2]);
  CHECK(residual[1] < residual[0] / 50);
  CHECK(residual[2] < residual[1] / 50);
  CHECK(residual[2] < 1e-3 * 1e-5 * hooke.norm());
}

// Energy, P, Hessian and projected Hessian finite (and the projection PSD) on every inverted
// and degenerate sample.
inline void check_finite(const Material& m, bool energy_defined_when_inverted = true) {
  for (const Sample& s : degenerate_samples()) {
    INFO(m.name(), " at ", s.name);
    if (energy_defined_when_inverted || s.F.determinant() > 0) CHECK(std::isfinite(m.energy(s.F)));
    CHECK(m.pk1(s.F).allFinite());
    const Mat9 H = m.hessian(s.F);
    CHECK(H.allFinite());
    const Mat9 projected = m.projected_hessian(s.F);
    REQUIRE(projected.allFinite());
    const test::SymmetricEigen eig = test::symmetric_eigen(projected);
    CHECK(eig.values.minCoeff() >= -1e-10 * std::max(1.0, projected.norm()));
  }
}

}  // namespace sinew::material_checks
