// polar_rotation (engine/math/polar_rotation.cpp): Newton's iteration for det F > 0, the
// rotation-variant SVD otherwise. Checked against U V^T of that SVD over spectra from near
// rest to singular values 5e3 apart, with the orthogonal factor's own conditioning as the
// tolerance; that Newton runs (newton_polar_rotation) on every spectrum within its
// threshold and declines past it and for inverted, zero and non-finite F; and for scale
// invariance from 1e-200 to 1e200.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "engine/math/polar_rotation.hpp"
#include "engine/math/rotation_variant_svd.hpp"

using namespace sinew;

namespace {

Mat3 uniform_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// The polar factor moves by |dF| / ((s_i + s_j) / 2) under a change dF of F: two answers
// each carrying F's rounding (a few eps |F|: 16 covers the products of one iteration or
// one SVD) through that are within twice that of each other.
double polar_tolerance(Vec3 singular_values) {
  std::sort(singular_values.data(), singular_values.data() + 3);
  return 2 * 16 * 2.2e-16 * singular_values(2) / (0.5 * (singular_values(0) + singular_values(1)));
}

Mat3 svd_rotation(const Mat3& F) {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  return svd.U * svd.V.transpose();
}

}  // namespace

TEST_CASE("polar rotation agrees with the SVD's U V^T from near rest to nearly flat F") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  // Singular values, largest first: near rest, large stretches, two equal, and smallest
  // ones approaching (2e-3: Newton) and passing (2e-4: the SVD) the fallback threshold
  // (s > ~5.4e-4 for (1, 1, s), polar_rotation.hpp).
  const std::array<Vec3, 7> spectra = {Vec3(1, 1, 1),       Vec3(1.1, 1.0, 0.95), Vec3(3, 1, 0.3),
                                       Vec3(2, 2, 0.5),      Vec3(1, 0.5, 0.5),    Vec3(1, 1, 2e-3),
                                       Vec3(1, 1, 2e-4)};
  for (const Vec3& spectrum : spectra)
    for (int i = 0; i < 200; ++i) {
      Vec3 s = spectrum;
      for (int k = 0; k < 3; ++k) s(k) *= 1 + jitter(rng);
      const Mat3 F = uniform_rotation(rng) * s.asDiagonal() * uniform_rotation(rng).transpose();
      const Mat3 R = polar_rotation(F);
      REQUIRE(R.allFinite());
      Mat3 newton;
      CHECK(newton_polar_rotation(F, newton) == (spectrum(2) > 1e-3));
      if (spectrum(2) > 1e-3) CHECK(newton == R);
      CHECK((R.transpose() * R - Mat3::Identity()).norm() <= 1e-14);
      CHECK(R.determinant() == doctest::Approx(1.0).epsilon(1e-14));
      CHECK((R - svd_rotation(F)).norm() <= polar_tolerance(s));
    }
}

TEST_CASE("polar rotation: Newton declines inverted, zero and non-finite F, which the SVD then serves") {
  std::mt19937 rng(13);
  const Mat3 Q = uniform_rotation(rng);
  Mat3 inverted = Q * Vec3(1.2, 0.9, -0.8).asDiagonal() * uniform_rotation(rng).transpose();
  Mat3 with_nan = Q;
  with_nan(1, 2) = std::numeric_limits<double>::quiet_NaN();
  Mat3 with_inf = Q;
  with_inf(0, 0) = std::numeric_limits<double>::infinity();
  Mat3 R = Mat3::Constant(7);
  for (const Mat3& F : {inverted, Mat3::Zero().eval(), with_nan, with_inf}) {
    CHECK_FALSE(newton_polar_rotation(F, R));
    CHECK(R == Mat3::Constant(7));  // untouched
  }
  CHECK((polar_rotation(inverted) - svd_rotation(inverted)).norm() == 0);
  CHECK(polar_rotation(with_nan) == Mat3::Identity());
}

TEST_CASE("polar rotation is scale invariant and leaves F itself when F is a rotation") {
  std::mt19937 rng(12);
  for (int i = 0; i < 100; ++i) {
    const Mat3 Q = uniform_rotation(rng);
    CHECK((polar_rotation(Q) - Q).norm() <= polar_tolerance(Vec3::Ones()));
    const Vec3 stretch(1.3, 0.9, 0.7);
    const Mat3 F = Q * stretch.asDiagonal() * uniform_rotation(rng).transpose();
    const Mat3 R = polar_rotation(F);
    for (const double scale : {1e-200, 1e-8, 1e8, 1e200}) {
      Mat3 scaled;
      CHECK(newton_polar_rotation(scale * F, scaled));  // the power-of-two prescaling
      CHECK((polar_rotation(scale * F) - R).norm() <= polar_tolerance(stretch));
    }
  }
}
