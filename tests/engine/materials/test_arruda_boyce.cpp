#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "engine/materials/arruda_boyce.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

namespace {

MaterialParameters ab_parameters(double nu, double n) {
  MaterialParameters p = parameters(nu);
  p.arruda_boyce_n = n;
  return p;
}

}  // namespace

TEST_CASE("Arruda-Boyce: Psi(I) = 0, P(I) = 0, no force under rotation, Hooke's law") {
  for (double n : {2.0, 8.0, 1e6})
    for (double nu : {0.3, 0.45}) {
      INFO("N = ", n, ", nu = ", nu);
      const MaterialParameters p = ab_parameters(nu, n);
      const ArrudaBoyce m(p);
      check_rest(m, p);
      check_hooke(m, p);
      CHECK(std::abs(m.energy(Mat3::Identity())) < 1e-20);
    }
  CHECK_THROWS_AS(ArrudaBoyce(ab_parameters(0.3, 0.0)), std::invalid_argument);
}

TEST_CASE("Arruda-Boyce: stiffens with stretch, more so for fewer chain segments") {
  // The series' higher terms stiffen as Ic grows toward the locking stretch sqrt(N).
  const Mat3 F = with_singular_values(Vec3(2.0, 1.0, 0.5));
  const double n2 = ArrudaBoyce(ab_parameters(0.3, 2)).pk1(F).norm();
  const double n8 = ArrudaBoyce(ab_parameters(0.3, 8)).pk1(F).norm();
  CHECK(n2 > n8);
}

TEST_CASE("Arruda-Boyce: P and Hessian against finite differences, shrinking step") {
  for (double n : {2.0, 8.0}) check_derivatives(ArrudaBoyce(ab_parameters(0.45, n)), samples());
}

TEST_CASE("Arruda-Boyce: closed-form eigensystem and projection") {
  const ArrudaBoyce m(ab_parameters(0.45, 8));
  for (const Sample& s : samples()) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("Arruda-Boyce: finite on inverted and degenerate F") {
  check_finite(ArrudaBoyce(ab_parameters(0.45, 8)));
}
