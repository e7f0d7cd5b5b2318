// The curvature of strain-limit rows (strain_limit_curvature.hpp): the Hessian in F by
// forward differences of the analytic Jacobian must equal second differences of the
// constraint values themselves, and the blocks SQP uses must be the positive part of the
// latter mapped to the tet's coordinates, symmetric, PSD and finite everywhere.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "tests/support/random_rotation.hpp"
#include "engine/constraints/strain_limit_curvature.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

const double kInf = std::numeric_limits<double>::infinity();

double value(const StrainLimitSpec& spec, const Mat3& F, int k) {
  const StrainLimitValues v = compute_strain_limit_values(spec, compute_rotation_variant_svd(F));
  REQUIRE((v.present >> k & 1u));
  return v.C[k];
}

// d2C_k/dF2 from values only: (C(++) - C(+-) - C(-+) + C(--)) / 4 step^2 off the diagonal,
// (C(+) - 2 C + C(-)) / step^2 on it. Error O(step^2) plus round-off ~1e-16 / step^2.
Mat9 second_differences(const StrainLimitSpec& spec, const Mat3& F, int k, double step) {
  Mat9 H;
  const auto E = [&](int e) {
    Mat3 d = Mat3::Zero();
    d(e % 3, e / 3) = step;
    return d;
  };
  for (int a = 0; a < 9; ++a)
    for (int b = 0; b < 9; ++b)
      H(a, b) = a == b ? (value(spec, F + E(a), k) - 2 * value(spec, F, k) + value(spec, F - E(a), k)) / (step * step)
                       : (value(spec, F + E(a) + E(b), k) - value(spec, F + E(a) - E(b), k) -
                          value(spec, F - E(a) + E(b), k) + value(spec, F - E(a) - E(b), k)) /
                             (4 * step * step);
  return H;
}

Mat43 tet_gradients() {
  const Vec3 X[4] = {Vec3(0.01, -0.02, 0.0), Vec3(0.11, 0.01, -0.01), Vec3(-0.02, 0.09, 0.02), Vec3(0.03, 0.02, 0.12)};
  Mat3 Dm;
  for (int a = 1; a < 4; ++a) Dm.col(a - 1) = X[a] - X[0];
  Mat43 dN;
  dN.bottomRows<3>() = Dm.inverse();
  dN.row(0) = -dN.bottomRows<3>().colwise().sum();
  return dN;
}

}  // namespace

TEST_CASE("strain limit curvature: the Hessian in F equals second differences of the values") {
  std::mt19937 rng(5);
  StrainLimitSpec spec;
  spec.smin = Vec3(0.9, 0.8, 0.95);
  spec.smax = Vec3(1.1, 1.3, 1.05);
  // Stretches apart (the paper's cosines) and two within kStrainLimitBlendGap (blended) but
  // beyond kCurvatureGap (where the probes' dV is exact).
  const Vec3 stretches[] = {Vec3(1.2, 1.0, 0.9), Vec3(1.035, 1.02, 0.9)};
  spec.pair_cuts = false;  // the cuts have no curvature block (next case)
  for (StrainLimitMode mode : {StrainLimitMode::Hyperbolic, StrainLimitMode::Orthogonal, StrainLimitMode::Linear}) {
    spec.mode = mode;
    for (const Vec3& s : stretches) {
      spec.frame = test::random_rotation(rng);
      const Mat3 F = test::random_rotation(rng) * s.asDiagonal() * test::random_rotation(rng).transpose();
      StrainLimitRows rows;
      evaluate_strain_limit(spec, F, Mat43::Zero(), kInf, 0, rows);
      REQUIRE(rows.count > 0);
      std::array<Mat9, kStrainRowIndexCount> hessians;
      strain_limit_hessians(spec, F, rows, hessians);
      double worst = 0;
      for (int r = 0; r < rows.count; ++r) {
        REQUIRE(hessians[r].allFinite());
        const double scale = std::max(hessians[r].norm(), 1.0);
        // The error of second differences falls like step^2 |d4C| until round-off (~1e-16 /
        // step^2 per entry, ~1e-6 at 1e-5); d4C grows like (s - 1) / gap^4, so stretches
        // 0.01 apart need the smaller steps. The best of 1e-4 and 1e-5 is compared.
        const auto error = [&](double step) {
          return (second_differences(spec, F, rows.row[r].index, step) - hessians[r]).norm() / scale;
        };
        const double coarse = error(1e-3), fine = std::min(error(1e-4), error(1e-5));
        CHECK(fine < coarse);
        worst = std::max(worst, fine);
      }
      MESSAGE("mode " << int(mode) << ", s = " << s.transpose() << ": worst relative difference " << worst);
      CHECK(worst < 1e-5);
    }
  }
}

TEST_CASE("strain limit curvature: blocks are the positive part of -d2C/dF2 in x, PSD and finite") {
  std::mt19937 rng(9);
  const Mat43 dN = tet_gradients();
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();  // dvec(F)/dx
  for (int a = 0; a < 4; ++a)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) B(r + 3 * c, 3 * a + r) = dN(a, c);
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0.75, 0.98);
  spec.smax = Vec3(1.05, 1.25, 1.02);
  spec.frame = test::random_rotation(rng);
  const Mat3 Q1 = test::random_rotation(rng), Q2 = test::random_rotation(rng);
  const Mat3 cases[] = {Q1 * Vec3(1.2, 1.0, 0.9).asDiagonal() * Q2.transpose(),
                        Q1 * Vec3(1.03, 1.03, 0.98).asDiagonal() * Q2.transpose(), Mat3::Identity(),
                        Q1 * Vec3(1.0, 0.0, 0.0).asDiagonal() * Q2.transpose(), Mat3::Zero()};
  for (StrainLimitMode mode : {StrainLimitMode::Hyperbolic, StrainLimitMode::Orthogonal, StrainLimitMode::Linear,
                               StrainLimitMode::Isotropic}) {
    spec.mode = mode;
    for (int c = 0; c < 5; ++c) {
      CAPTURE(c);
      StrainLimitRows rows;
      evaluate_strain_limit(spec, cases[c], dN, kInf, 0, rows);
      std::array<Mat12, kStrainRowIndexCount> blocks;
      compute_strain_limit_curvatures(spec, cases[c], dN, rows, blocks);
      std::array<Mat9, kStrainRowIndexCount> hessians;
      if (mode != StrainLimitMode::Isotropic) strain_limit_hessians(spec, cases[c], rows, hessians);
      for (int r = 0; r < rows.count; ++r) {
        REQUIRE(blocks[r].allFinite());
        const double scale = std::max(blocks[r].norm(), 1e-300);
        CHECK((blocks[r] - blocks[r].transpose()).norm() <= 1e-12 * scale);
        CHECK(test::min_eigenvalue(blocks[r]) >= -1e-10 * scale);
        // A pair cut (the near-equal stretches of case 1, and rest) holds a material
        // direction its probes would not: no block (strain_limit_curvature.hpp).
        if (rows.row[r].index >= kStrainCutFirst) CHECK(blocks[r].norm() == 0);
        // Against a reference built without the code under test, where C is smooth (case 0:
        // stretches 0.1 apart): the positive part of -(second differences of the values),
        // mapped by B. Clamping eigenvalues is the projection onto the PSD cone, which moves
        // matrices apart by at most their distance (Frobenius), and |B^T X B| <= |B|_2^2 |X|;
        // the Hessians agree within 1e-5 relative (test above).
        if (mode == StrainLimitMode::Isotropic || c != 0) continue;
        const Mat9 H = second_differences(spec, cases[c], rows.row[r].index, 1e-4);
        const test::SymmetricEigen eigen = test::symmetric_eigen(-0.5 * (H + H.transpose()));
        const Mat9 positive =
            eigen.vectors * eigen.values.cwiseMax(0.0).asDiagonal() * eigen.vectors.transpose();
        const double B2 = test::singular_values(B)(0);
        CHECK((blocks[r] - B.transpose() * positive * B).norm() <= B2 * B2 * 1e-5 * std::max(H.norm(), 1.0));
      }
    }
  }
}

TEST_CASE("strain limit curvature: bounded as two stretches meet, whichever side the probes fall") {
  // Closer than kCurvatureGap the curvature is taken at stretches kCurvatureGap apart (same
  // U, V). Unguarded, it grew like 1 / gap (V turns that fast, and so does the clamped dV
  // coupling), reaching ~1 / probe step once a probe swapped the axes' order: 160-300 times
  // its value at a gap of 1e-3 for these F. Here F = Q1 diag(1.04, 1.04, 0.97) Q2^T plus a
  // random perturbation of size eps, which picks U and V in the plane at random; as eps
  // falls from 1e-3 to 0 the largest block must stay below the largest over 64 bases of the
  // plane with the stretches the floor apart (the same family of F), up to 25 %: the
  // perturbation moves the stretches by up to ~eps, 10 % of the floor, and the Hessian
  // scales like 1 / gap^2 there; the 64 samples of a smooth function of the angle miss its
  // maximum by far less.
  std::mt19937 rng(13);
  std::normal_distribution<double> normal(0, 1);
  const Mat43 dN = tet_gradients();
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0.75, 0.98);
  spec.smax = Vec3(1.05, 1.25, 1.02);
  const auto largest_block = [&](const Mat3& F) {
    StrainLimitRows rows;
    evaluate_strain_limit(spec, F, dN, kInf, 0, rows);
    std::array<Mat12, kStrainRowIndexCount> blocks;
    compute_strain_limit_curvatures(spec, F, dN, rows, blocks);
    double largest = 0;
    for (int r = 0; r < rows.count; ++r) {
      REQUIRE(blocks[r].allFinite());
      largest = std::max(largest, blocks[r].norm());
    }
    return largest;
  };
  const auto in_plane = [](double angle) {
    return Mat3(Eigen::AngleAxisd(angle, Vec3::UnitZ()));  // turns axes 0 and 1 of diag(.)
  };
  for (StrainLimitMode mode : {StrainLimitMode::Hyperbolic, StrainLimitMode::Orthogonal, StrainLimitMode::Linear}) {
    spec.mode = mode;
    for (int trial = 0; trial < 3; ++trial) {
      spec.frame = test::random_rotation(rng);
      const Mat3 Q1 = test::random_rotation(rng), Q2 = test::random_rotation(rng);
      double reference = 0;
      for (int b = 0; b < 64; ++b) {
        const Mat3 R = in_plane(M_PI * b / 64);
        const Vec3 apart(1.04 + kCurvatureGap * 1.04 + 4 * kCurvatureStep, 1.04, 0.97);
        reference = std::max(reference, largest_block(Q1 * R * apart.asDiagonal() * R.transpose() * Q2.transpose()));
      }
      REQUIRE(reference > 0);
      for (const double eps : {1e-3, 1e-4, 1e-5, 2e-6, 1e-6, 5e-7, 1e-8, 0.0}) {
        CAPTURE(eps);
        Mat3 E;
        for (int e = 0; e < 9; ++e) E(e % 3, e / 3) = eps * normal(rng);
        const double ratio = largest_block(Q1 * Vec3(1.04, 1.04, 0.97).asDiagonal() * Q2.transpose() + E) / reference;
        MESSAGE("mode " << int(mode) << " eps " << eps << " ratio " << ratio);
        CHECK(ratio <= 1.25);
      }
    }
  }
}
