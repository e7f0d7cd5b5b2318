#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "engine/materials/invariant_material.hpp"
#include "engine/materials/neo_hookean.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

TEST_CASE("Neo-Hookean: P(I) = 0, no force under rotation, Hooke's law with mu_L, lambda_L") {
  for (double nu : {0.0, 0.3, 0.45}) {
    INFO("nu = ", nu);
    const MaterialParameters p = parameters(nu);
    const NeoHookean m(p);
    check_rest(m, p);
    check_hooke(m, p);
    CHECK(std::abs(m.energy(Mat3::Identity())) < 1e-20);
  }
}

TEST_CASE("Neo-Hookean: P and Hessian against finite differences where J > 0") {
  for (double nu : {0.3, 0.45}) check_derivatives(NeoHookean(parameters(nu)), samples(false));
}

TEST_CASE("Neo-Hookean: closed-form eigensystem and projection where J > 0") {
  const NeoHookean m(parameters(0.45));
  for (const Sample& s : samples(false)) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("Neo-Hookean: J <= 0 is reported, never NaN") {
  const NeoHookean m(parameters(0.45));
  CHECK(m.is_defined(Mat3::Identity()));
  CHECK(m.is_defined(with_singular_values(Vec3(1.3, 0.9, 0.75))));
  check_finite(m, false);
  // Defined iff det F > 0 as computed (a numerically flat F may come out with J = +1e-17).
  for (const Sample& s : degenerate_samples()) {
    INFO(s.name);
    const bool defined = s.F.determinant() > 0;
    CHECK(m.is_defined(s.F) == defined);
    CHECK((m.energy(s.F) == std::numeric_limits<double>::infinity()) == !defined);
  }
  for (const Mat3& F : {Mat3(-Mat3::Identity()), Mat3(Vec3(1, 1, -1).asDiagonal()),
                        Mat3(Vec3(1, 1, 0).asDiagonal()), Mat3(Mat3::Zero())}) {
    CHECK_FALSE(m.is_defined(F));
    CHECK(m.energy(F) == std::numeric_limits<double>::infinity());
  }
  // Inverted: P uses g' frozen at kMinJ, so the force -P increases J: -P : cof(F) > 0.
  const Mat3 F = with_singular_values(Vec3(1.3, 0.9, -0.6));
  CHECK((-m.pk1(F)).cwiseProduct(cofactor_matrix(F)).sum() > 0);
  // Just above J = 0 the energy is finite and grows as J falls.
  const Mat3 thin = with_singular_values(Vec3(1, 1, 1e-3));
  CHECK(m.is_defined(thin));
  CHECK(std::isfinite(m.energy(thin)));
  CHECK(m.energy(thin) > m.energy(with_singular_values(Vec3(1, 1, 1e-2))));
}
