#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "engine/core/cpu_features.hpp"
#include "engine/math/rotation_variant_svd.hpp"
#include "tests/support/dense_decompositions.hpp"

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

namespace {

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q;
  q.w() = n(rng);
  q.x() = n(rng);
  q.y() = n(rng);
  q.z() = n(rng);
  return q.normalized().toRotationMatrix();
}

// |S| against an independent SVD (Eigen's two-sided Jacobi, tests/support): a backward-stable
// SVD has singular values within a small multiple of eps |F| of the exact ones.
void check_against_reference(const Mat3& F) {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  const VecX reference = test::singular_values(F);
  const double largest = std::max(reference(0), std::numeric_limits<double>::min());
  for (int k = 0; k < 3; ++k) CHECK(std::abs(std::abs(svd.S(k)) - reference(k)) <= 1e-14 * largest);
  CHECK((svd.U * svd.S.asDiagonal() * svd.V.transpose() - F).norm() <= 1e-14 * largest);
  // V is a product of plane rotations, each exact to a few eps: 1e-14 allows ~15 of them at
  // 3 eps (5 sweeps, the most measured on 100,000 random F; rotation_variant_svd.cpp).
  CHECK((svd.V.transpose() * svd.V - Mat3::Identity()).norm() <= 1e-14);
}

}  // namespace

TEST_CASE("rotation-variant SVD agrees with a reference SVD, also near repeated and zero values") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 300; ++i) {
    const Mat3 P = random_rotation(rng), Q = random_rotation(rng);
    const double a = std::exp(3 * u(rng));
    // Generic, two equal, two within 1e-13, all three equal, rank 2 and rank 1 spectra,
    // with a reflection in half the cases.
    const double sign = i % 2 ? -1 : 1;
    const std::array<Vec3, 6> spectra = {Vec3(a, 1, 0.3 * a), Vec3(a, a, 0.5), Vec3(a, a * (1 + 1e-13), 1),
                                         Vec3(a, a, a), Vec3(a, 0.7, 0), Vec3(a, 0, 0)};
    for (const Vec3& s : spectra) {
      const Mat3 F = P * Vec3(s(0), s(1), sign * s(2)).asDiagonal() * Q.transpose();
      check_decomposition(F);
      check_against_reference(F);
    }
  }
}

TEST_CASE("rotation-variant SVD is scale-invariant over the whole double range") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2, 2);
  // Down to subnormal scales (below 1 / DBL_MAX ~ 5.6e-309 a reciprocal would overflow).
  for (const double scale : {1e-312, 1e-300, 1e-150, 1e-20, 1e20, 1e150, 1e300}) {
    Mat3 F;
    for (int k = 0; k < 9; ++k) F(k) = u(rng);
    const RotationVariantSvd unit = compute_rotation_variant_svd(F);
    const RotationVariantSvd scaled = compute_rotation_variant_svd(scale * F);
    REQUIRE(scaled.S.allFinite());
    // At a subnormal scale, scale * F is itself rounded to multiples of denorm_min (9 entries
    // by at most denorm_min / 2: 1.5 denorm_min in Frobenius norm, which bounds how far the
    // singular values move, Mirsky), and so is each of the 3 values of S (at most 0.87
    // denorm_min together): 3 denorm_min bounds the sum, relative to scale.
    const double input_rounding = 3 * std::numeric_limits<double>::denorm_min() / scale;
    CHECK((scaled.S / scale - unit.S).norm() <= 1e-14 * unit.S.norm() + input_rounding);
    if (input_rounding > 1e-16) continue;  // U and V move by that over the gaps: not comparable
    CHECK((scaled.U - unit.U).norm() <= 1e-12);
    CHECK((scaled.V - unit.V).norm() <= 1e-12);
  }
}

TEST_CASE("rotation-variant SVD of a non-finite matrix reports NaN singular values") {
  Mat3 F = Mat3::Identity();
  F(1, 2) = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(compute_rotation_variant_svd(F).S.allFinite());
  CHECK(compute_rotation_variant_svd(F).U.allFinite());
  CHECK(compute_rotation_variant_svd(F).V.allFinite());
  F(1, 2) = std::numeric_limits<double>::infinity();
  CHECK_FALSE(compute_rotation_variant_svd(F).S.allFinite());
}

TEST_CASE("rotation-variant SVD: the branches that random matrices rarely reach") {
  // Nearly parallel columns of very different lengths: |zeta| > 1e100 in the rotation.
  Mat3 F = Mat3::Zero();
  F(0, 0) = 1;
  F(0, 1) = F(1, 1) = 1e-110;
  check_decomposition(F);
  check_against_reference(F);
  // Orthogonal columns out of order, one reflected: no rotation, an odd number of swaps.
  check_decomposition(Vec3(1, -2, 3).asDiagonal());
  check_against_reference(Vec3(1, -2, 3).asDiagonal());
  // Exactly rank 1 along a non-axis direction: U's second column is any unit vector
  // orthogonal to the first (Eigen's unitOrthogonal).
  Mat3 line = Mat3::Zero();
  line.col(0) = Vec3(1, 2, 3);
  check_decomposition(line);
  check_against_reference(line);
  const RotationVariantSvd svd = compute_rotation_variant_svd(line);
  CHECK(svd.S(1) == 0);
  CHECK(svd.S(2) == 0);
  // A subnormal matrix: finite, and its singular values exact up to rounding.
  const RotationVariantSvd tiny = compute_rotation_variant_svd(1e-310 * Mat3::Identity());
  REQUIRE(tiny.S.allFinite());
  CHECK(tiny.S(0) == doctest::Approx(1e-310).epsilon(1e-12));
  CHECK(std::abs(tiny.S(2)) == doctest::Approx(1e-310).epsilon(1e-12));
}

namespace {

bool same_bits(const Mat3& a, const Mat3& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 9) == 0; }

// Matrices that take the Jacobi sweeps' every branch, in an order that puts each kind in
// every lane of a group of four: near rotations (few sweeps), random ones (more), repeated
// and zero singular values, reflections, a rank-1 and a zero matrix (no rotation at all, or
// no sweep), non-finite entries (no sweep), subnormal and huge scales.
std::vector<Mat3> svd_batch_inputs() {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0, 1);
  const auto random = [&](double spread) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += spread * normal(rng);
    return F;
  };
  std::vector<Mat3> out;
  for (int i = 0; i < 200; ++i) {
    out.push_back(Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix() *
                  random(0.02));
    out.push_back(random(1.0));
  }
  Mat3 line = Mat3::Zero();
  line.col(0) = Vec3(1, 2, 3);
  const double inf = std::numeric_limits<double>::infinity();
  Mat3 not_finite = Mat3::Identity();
  not_finite(1, 2) = inf;
  Mat3 parallel = Mat3::Zero();
  parallel(0, 0) = 1;
  parallel(0, 1) = parallel(1, 1) = 1e-110;
  for (const Mat3& special :
       {Mat3(Mat3::Identity()), Mat3(Mat3::Zero()), line, not_finite, parallel, Mat3(Vec3(1, -2, 3).asDiagonal()),
        Mat3(Vec3(2, 2, 0.5).asDiagonal() * Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()).toRotationMatrix()),
        Mat3(1e-310 * Mat3::Identity()), Mat3(1e300 * random(1.0)), Mat3(-Mat3::Identity())})
    for (int copy = 0; copy < 4; ++copy) {
      out.push_back(special);
      out.push_back(random(0.5));  // shifts the special one's lane
      out.push_back(random(0.01));
    }
  return out;
}

}  // namespace

TEST_CASE("rotation-variant SVDs in batches equal one at a time, bit for bit, on either kernel path") {
  const std::vector<Mat3> F = svd_batch_inputs();
  for (const bool avx2 : {true, false}) {
    CAPTURE(avx2);
    std::optional<BaselineKernelsOnly> baseline;
    if (!avx2) baseline.emplace();
    if (avx2 && !use_avx2()) MESSAGE("no AVX2 on this CPU: both passes take the baseline path");
    // Counts that leave 0, 1, 2 and 3 matrices beyond the last group of four, and fewer than four.
    const int whole = static_cast<int>(F.size()) / 4 * 4;
    for (const int count : {whole, whole - 3, whole - 2, whole - 1, 3, 1}) {
      CAPTURE(count);
      std::vector<RotationVariantSvd> batch(count);
      compute_rotation_variant_svds(F.data(), batch.data(), count);
      int differing = 0;
      for (int k = 0; k < count; ++k) {
        const RotationVariantSvd one = compute_rotation_variant_svd(F[k]);
        const bool S_equal = std::memcmp(one.S.data(), batch[k].S.data(), sizeof(double) * 3) == 0;
        if (!(same_bits(one.U, batch[k].U) && same_bits(one.V, batch[k].V) && S_equal)) ++differing;
      }
      CHECK(differing == 0);
    }
  }
}
