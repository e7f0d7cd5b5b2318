#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "engine/materials/fung.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

namespace {

MaterialParameters fung_parameters(double nu, double c) {
  MaterialParameters p = parameters(nu);
  p.fung_c = c;
  return p;
}

}  // namespace

TEST_CASE("Fung: Psi(I) = 0, P(I) = 0, no force under rotation, Hooke's law") {
  // c = 2 at nu = 0.3 makes the matched lambda negative: Hooke must still hold.
  for (double c : {0.5, 1.0, 2.0})
    for (double nu : {0.3, 0.45}) {
      INFO("c = ", c, ", nu = ", nu);
      const MaterialParameters p = fung_parameters(nu, c);
      const Fung m(p);
      check_rest(m, p);
      check_hooke(m, p);
      CHECK(std::abs(m.energy(Mat3::Identity())) < 1e-20);
    }
  CHECK(Fung(fung_parameters(0.3, 2.0)).lambda() < 0);
  CHECK_THROWS_AS(Fung(fung_parameters(0.3, 0.0)), std::invalid_argument);
}

TEST_CASE("Fung: P and Hessian against finite differences, shrinking step") {
  for (double c : {0.5, 2.0}) check_derivatives(Fung(fung_parameters(0.45, c)), samples());
}

TEST_CASE("Fung: closed-form eigensystem and projection") {
  const Fung m(fung_parameters(0.45, 1.0));
  for (const Sample& s : samples()) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("Fung: finite on inverted, degenerate and hugely stretched F") {
  const Fung m(fung_parameters(0.45, 1.0));
  check_finite(m);
  // Past kMaxExponent the exponential is Taylor-continued: finite, and still C^2 there
  // (P from finite differences of the energy across the switch point).
  const double s = std::sqrt((Fung::kMaxExponent + 3 - 2) / 1.0);  // Ic - 3 = kMaxExponent
  const Mat3 F = with_singular_values(Vec3(s, 1, 1));
  CHECK(std::isfinite(m.energy(with_singular_values(Vec3(1e3, 1, 1)))));
  CHECK(m.hessian(with_singular_values(Vec3(1e3, 1, 1))).allFinite());
  const auto errors = gradient_errors(m, F, {1e-4, 1e-5});
  CHECK(errors[1] < 1e-6);
}
