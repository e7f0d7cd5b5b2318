#include <doctest/doctest.h>

#include <Eigen/LU>

#include "engine/materials/invariant_material.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

TEST_CASE("cofactor matrix is dJ/dF = J F^-T") {
  const Mat3 F = with_singular_values(Vec3(1.3, 0.9, -0.6));
  CHECK((cofactor_matrix(F) - F.determinant() * F.inverse().transpose()).norm() < 1e-13);
  CHECK((F.transpose() * cofactor_matrix(F) - F.determinant() * Mat3::Identity()).norm() < 1e-13);
  // Finite for a singular F (where F^-T is not).
  CHECK(cofactor_matrix(Mat3::Zero()).norm() == 0);
}

TEST_CASE("cofactor Hessian is d(cof F)/dF, exactly: cof is quadratic in F") {
  // Central differences are exact for a quadratic up to round-off (~1e-16 / h with h = 1e-3).
  const Mat3 F = with_singular_values(Vec3(1.3, 0.9, 0.75));
  const Mat9 H = cofactor_hessian(F);
  CHECK((H - H.transpose()).norm() == 0);
  const double h = 1e-3;
  for (int a = 0; a < 9; ++a) {
    const Vec9 fd = vec9(cofactor_matrix(F + h * unit(a)) - cofactor_matrix(F - h * unit(a))) / (2 * h);
    CHECK((fd - H.col(a)).norm() < 1e-10);
  }
  // J is cubic and homogeneous: vec(F)^T H_J vec(F) = 6 J (Euler's theorem twice).
  CHECK(vec9(F).dot(H * vec9(F)) == doctest::Approx(6 * F.determinant()).epsilon(1e-13));
}
