#include <doctest/doctest.h>

#include "engine/materials/corotational.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

TEST_CASE("corotational: P(I) = 0, no force under rotation, Hooke's law with mu_L, lambda_L") {
  for (double nu : {0.0, 0.3, 0.45}) {
    INFO("nu = ", nu);
    const MaterialParameters p = parameters(nu);
    const Corotational m(p);
    check_rest(m, p);
    check_hooke(m, p);
  }
}

TEST_CASE("corotational: energy is eq. 3 with R, S the polar decomposition") {
  const MaterialParameters p = parameters(0.3);
  const LameParameters lame = lame_parameters(p);
  const Corotational m(p);
  // F = Q diag(2, 1, 0.5): R = Q, S = diag(2, 1, 0.5).
  const Mat3 Q = Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  const Mat3 F = Q * Vec3(2, 1, 0.5).asDiagonal();
  const double expected = lame.mu * (1 + 0 + 0.25) + lame.lambda / 2 * 0.25;
  CHECK(m.energy(F) == doctest::Approx(expected).epsilon(1e-12));
  // Inverted: S carries the reflection (rotation-variant SVD), R stays a rotation.
  const Mat3 inverted = Q * Vec3(1, 1, -1).asDiagonal();
  CHECK(m.energy(inverted) == doctest::Approx(lame.mu * 4 + lame.lambda / 2 * 4).epsilon(1e-12));
}

TEST_CASE("corotational: P and Hessian against finite differences, shrinking step") {
  for (double nu : {0.3, 0.45}) check_derivatives(Corotational(parameters(nu)), samples());
}

TEST_CASE("corotational: closed-form eigensystem and projection") {
  const Corotational m(parameters(0.45));
  for (const Sample& s : samples()) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("corotational: finite on inverted and degenerate F (twist denominator floored)") {
  const Corotational m(parameters(0.45));
  check_finite(m);
  // F = diag(1, 1, -1): sigma_1 + sigma_2 = 0, R is not unique and the true Hessian is
  // unbounded; the floored twist value is finite, negative, and clamped by the projection.
  const SvdEigensystem system = m.eigensystem(Vec3(1, 1, -1).asDiagonal());
  CHECK(system.twist(0) < 0);
  CHECK(std::isfinite(system.twist(0)));
}
