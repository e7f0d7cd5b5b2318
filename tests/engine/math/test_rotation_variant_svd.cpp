#include <doctest/doctest.h>

#include <random>

#include "engine/math/rotation_variant_svd.hpp"

using namespace sinew;

namespace {

void check_decomposition(const Mat3& F) {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  REQUIRE(svd.U.allFinite());
  REQUIRE(svd.V.allFinite());
  REQUIRE(svd.S.allFinite());
  const double scale = std::max(1.0, F.norm());
  CHECK((svd.U * svd.S.asDiagonal() * svd.V.transpose() - F).norm() <= 1e-12 * scale);
  CHECK(svd.U.determinant() == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(svd.V.determinant() == doctest::Approx(1.0).epsilon(1e-12));
  CHECK((svd.U.transpose() * svd.U - Mat3::Identity()).norm() <= 1e-12);
  CHECK(std::abs(svd.S(0)) >= std::abs(svd.S(1)));
  CHECK(std::abs(svd.S(1)) >= std::abs(svd.S(2)));
  CHECK(svd.S(0) >= 0);
  CHECK(svd.S(1) >= 0);
  // The sign of the product of singular values is the sign of det F.
  if (std::abs(F.determinant()) > 1e-9 * scale * scale * scale)
    CHECK((svd.S.prod() > 0) == (F.determinant() > 0));
}

}  // namespace

TEST_CASE("rotation-variant SVD reconstructs F with rotations and puts reflections in S") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 1000; ++i) {
    Mat3 F;
    for (int k = 0; k < 9; ++k) F(k) = u(rng);
    check_decomposition(F);
  }
}

TEST_CASE("rotation-variant SVD of degenerate and repeated cases stays finite") {
  Mat3 reflection = Mat3::Identity();
  reflection(0, 0) = -1;
  check_decomposition(Mat3::Identity());
  check_decomposition(reflection);
  check_decomposition(Mat3::Zero());
  check_decomposition(Vec3(2, 2, 0).asDiagonal());           // flat
  check_decomposition(Vec3(1, 0, 0).asDiagonal());           // line
  check_decomposition(Vec3(1, 1, 1e-300).asDiagonal());
  check_decomposition(-Mat3::Identity());                    // full inversion
  const RotationVariantSvd r = compute_rotation_variant_svd(reflection);
  CHECK(r.S(2) == doctest::Approx(-1));
}
