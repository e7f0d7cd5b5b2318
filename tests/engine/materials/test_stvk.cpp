#include <doctest/doctest.h>

#include "engine/materials/stvk.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

TEST_CASE("StVK: P(I) = 0, no force under rotation, Hooke's law with mu_L, lambda_L") {
  for (double nu : {0.0, 0.3, 0.45}) {
    INFO("nu = ", nu);
    const MaterialParameters p = parameters(nu);
    const Stvk m(p);
    check_rest(m, p);
    check_hooke(m, p);
  }
}

TEST_CASE("StVK: P and Hessian against finite differences, shrinking step") {
  for (double nu : {0.3, 0.45}) check_derivatives(Stvk(parameters(nu)), samples());
}

TEST_CASE("StVK: closed-form eigensystem and projection") {
  const Stvk m(parameters(0.45));
  for (const Sample& s : samples()) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("StVK: finite on inverted and degenerate F; no resistance to full inversion") {
  const Stvk m(parameters(0.45));
  check_finite(m);
  CHECK(m.energy(-Mat3::Identity()) == 0.0);  // E = (F^T F - I)/2 = 0 exactly
  CHECK(m.pk1(-Mat3::Identity()).norm() < 1e-20);
}
