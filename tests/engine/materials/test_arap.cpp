#include <doctest/doctest.h>

#include "engine/materials/arap.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

TEST_CASE("ARAP: P(I) = 0, no force under rotation, linearisation 2 mu_L eps (no volume term)") {
  const MaterialParameters p = parameters(0.3);
  const Arap m(p);
  check_rest(m, p);
  check_hooke(m, p, false);
  // Energy mu ||F - R||^2 = mu sum (sigma - 1)^2, blind to volume beyond that.
  const Mat3 F = with_singular_values(Vec3(2, 1, 0.5));
  CHECK(m.energy(F) == doctest::Approx(lame_parameters(p).mu * 1.25).epsilon(1e-12));
}

TEST_CASE("ARAP: P and Hessian against finite differences, shrinking step") {
  check_derivatives(Arap(parameters(0.3)), samples());
}

TEST_CASE("ARAP: closed-form eigensystem and projection") {
  const Arap m(parameters(0.3));
  for (const Sample& s : samples()) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("ARAP: finite on inverted and degenerate F") { check_finite(Arap(parameters(0.3))); }
