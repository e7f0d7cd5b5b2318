#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "tests/support/random_rotation.hpp"
#include "engine/math/svd_derivative.hpp"

using namespace sinew;

namespace {

// The SVD of G with each (u_k, v_k) pair's sign matched to `ref`, so that finite differences
// follow one smooth branch (Jacobi may flip a pair between nearby matrices).
RotationVariantSvd aligned_svd(const Mat3& G, const RotationVariantSvd& ref) {
  RotationVariantSvd r = compute_rotation_variant_svd(G);
  for (int k = 0; k < 3; ++k)
    if (r.V.col(k).dot(ref.V.col(k)) < 0) {
      r.V.col(k) *= -1;
      r.U.col(k) *= -1;
    }
  // A flip of u_2 and v_2 alone turns S(2)'s sign: match it too (only when S(2) ~ 0).
  if (r.U.col(2).dot(ref.U.col(2)) < 0) {
    r.U.col(2) *= -1;
    r.S(2) *= -1;
  }
  return r;
}

// Largest relative error of dU, dS, dV (all nine entries of F) against central differences.
double fd_error(const Mat3& F, double step) {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  const SvdDerivative d = compute_svd_derivative(svd);
  double worst = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      Mat3 E = Mat3::Zero();
      E(r, c) = step;
      const RotationVariantSvd p = aligned_svd(F + E, svd), m = aligned_svd(F - E, svd);
      const Mat3 fdU = (p.U - m.U) / (2 * step), fdV = (p.V - m.V) / (2 * step);
      const Vec3 fdS = (p.S - m.S) / (2 * step);
      const double scale = 1 + d.dU[r][c].norm() + d.dV[r][c].norm() + d.dS[r][c].norm();
      worst = std::max(worst, (fdU - d.dU[r][c]).norm() / scale);
      worst = std::max(worst, (fdV - d.dV[r][c]).norm() / scale);
      worst = std::max(worst, (fdS - d.dS[r][c]).norm() / scale);
    }
  return worst;
}

// Singular values with every gap |s_k -+ s_l| at least `gap`.
Mat3 random_separated(std::mt19937& rng, bool inverted) {
  std::uniform_real_distribution<double> u(0.3, 2.0);
  Vec3 s;
  do {
    s = Vec3(u(rng), u(rng), u(rng));
    std::sort(s.data(), s.data() + 3, [](double a, double b) { return a > b; });
  } while (s(0) - s(1) < 0.1 || s(1) - s(2) < 0.1);
  if (inverted) s(2) = -s(2);
  return test::random_rotation(rng) * s.asDiagonal() * test::random_rotation(rng).transpose();
}

}  // namespace

TEST_CASE("SVD derivative: dU, dS, dV equal finite differences away from repeated values") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 F = random_separated(rng, trial % 2 == 1);  // odd trials: inverted, S(2) < 0
    double previous = 1e300;
    for (double step : {1e-2, 1e-3, 1e-4}) {
      const double error = fd_error(F, step);
      if (trial == 0) MESSAGE("FD step " << step << ": relative error " << error);
      CHECK(error < previous);  // central differences: the error falls like step^2
      previous = error;
    }
    CHECK(previous < 1e-6);
  }
}

TEST_CASE("SVD derivative: a single zero singular value is not a repeated one") {
  // The rotation-variant SVD lets S(2) pass through zero with its sign, smoothly: a
  // flattened element has exact derivatives.
  std::mt19937 rng(3);
  const Mat3 F =
      test::random_rotation(rng) * Vec3(1.7, 0.8, 0.0).asDiagonal() * test::random_rotation(rng).transpose();
  const double error = fd_error(F, 1e-4);
  MESSAGE("relative error with S(2) = 0: " << error);
  CHECK(error < 1e-6);
}

TEST_CASE("SVD derivative: the differential reconstructs dF, and Omegas are antisymmetric") {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0, 1);
  const Mat3 F = random_separated(rng, true);
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  Mat3 dF;
  for (int k = 0; k < 9; ++k) dF(k) = n(rng);
  const SvdDifferential d = compute_svd_differential(svd, dF);
  CHECK((d.omega_U + d.omega_U.transpose()).norm() == 0);
  CHECK((d.omega_V + d.omega_V.transpose()).norm() == 0);
  const Mat3 S = svd.S.asDiagonal();
  const Mat3 rebuilt = d.dU * S * svd.V.transpose() +
                       svd.U * Mat3(d.dS.asDiagonal()) * svd.V.transpose() +
                       svd.U * S * d.dV.transpose();
  CHECK((rebuilt - dF).norm() < 1e-12 * dF.norm());
  // The per-entry derivative is the differential along e_r e_c^T.
  const SvdDerivative all = compute_svd_derivative(svd);
  Mat3 E12 = Mat3::Zero();
  E12(1, 2) = 1;
  const SvdDifferential e12 = compute_svd_differential(svd, E12);
  CHECK((all.dU[1][2] - e12.dU).norm() < 1e-14);
  CHECK((all.dV[1][2] - e12.dV).norm() < 1e-14);
  CHECK((all.dS[1][2] - e12.dS).norm() < 1e-14);
  // V's rotation rate alone: Omega_V's upper entries, the same as the full derivative's.
  const SvdRotationDerivative rotation = compute_svd_rotation_derivative(svd);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const Mat3 omega_V = svd.V.transpose() * all.dV[r][c];
      CHECK((rotation.omega_V[r][c] - Vec3(omega_V(0, 1), omega_V(0, 2), omega_V(1, 2))).norm() < 1e-13);
    }
}

TEST_CASE("SVD derivative: repeated and zero singular values give finite, bounded results") {
  // Behaviour (svd_derivative.hpp): each pair's denominators s_l - s_k and s_l + s_k are
  // clamped to magnitude eps = tol * max(|S(0)|, 1), so |Omega(k, l)| <= (|A_kl| + |A_lk|) / eps
  // <= 2 / eps for a unit dF = e_r e_c^T (|A| entries <= 1), and the rotation part of dF
  // (antisymmetric A) is still exact wherever s_k + s_l >= eps.
  std::mt19937 rng(9);
  const Mat3 Q1 = test::random_rotation(rng), Q2 = test::random_rotation(rng);
  const Mat3 cases[] = {
      Mat3::Identity(),                                                // triple repeat
      Q1 * Vec3(1.3, 1.3, 0.7).asDiagonal() * Q2.transpose(),          // repeated pair
      Q1 * Vec3(1.3, 0.7, -0.7).asDiagonal() * Q2.transpose(),         // pair summing to zero
      Q1 * Vec3(1.0, 1.0 - 1e-12, 0.5).asDiagonal() * Q2.transpose(),  // nearly repeated
      Q1 * Vec3(1.0, 0.0, 0.0).asDiagonal() * Q2.transpose(),          // a line: two zeros
      Mat3::Zero(),
      -Mat3::Identity(),
  };
  const double tol = kSvdGapTolerance;
  for (const Mat3& F : cases) {
    const RotationVariantSvd svd = compute_rotation_variant_svd(F);
    const double eps = tol * std::max(std::abs(svd.S(0)), 1.0);
    const SvdDerivative d = compute_svd_derivative(svd, tol);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        REQUIRE(d.dU[r][c].allFinite());
        REQUIRE(d.dV[r][c].allFinite());
        REQUIRE(d.dS[r][c].allFinite());
        const Mat3 omega_U = svd.U.transpose() * d.dU[r][c];
        const Mat3 omega_V = svd.V.transpose() * d.dV[r][c];
        CHECK(omega_U.cwiseAbs().maxCoeff() <= 2 / eps * (1 + 1e-12));
        CHECK(omega_V.cwiseAbs().maxCoeff() <= 2 / eps * (1 + 1e-12));
        // The strain limits' lean form clamps alike.
        const Vec3 lean = compute_svd_rotation_derivative(svd, tol).omega_V[r][c];
        CHECK((lean - Vec3(omega_V(0, 1), omega_V(0, 2), omega_V(1, 2))).norm() <= 1e-12 * (1 + omega_V.norm()));
      }
  }
  // At F = I (U = V), a rotation dF = W (antisymmetric) is reproduced exactly:
  // dU - dV = W U, and dS = 0.
  const RotationVariantSvd id = compute_rotation_variant_svd(Mat3::Identity());
  Mat3 W;
  W << 0, -0.3, 0.2, 0.3, 0, -0.5, -0.2, 0.5, 0;
  const SvdDifferential dw = compute_svd_differential(id, W, tol);
  CHECK((dw.dU - dw.dV - W * id.U).norm() < 1e-14);
  CHECK(dw.dS.norm() < 1e-15);
}

TEST_CASE("SVD derivative: the clamp is continuous and saturates as two values meet") {
  // |Omega| grows like 1 / gap until gap = eps, then stays at its value for gap = eps.
  std::mt19937 rng(21);
  const Mat3 Q1 = test::random_rotation(rng), Q2 = test::random_rotation(rng);
  const double tol = 1e-4;
  auto coupling = [&](double gap) {
    const Mat3 F = Q1 * Vec3(1.0 + gap, 1.0, 0.5).asDiagonal() * Q2.transpose();
    const RotationVariantSvd svd = compute_rotation_variant_svd(F);
    // The symmetric perturbation of the pair, u_0 v_1^T + u_1 v_0^T: A_01 = A_10 = 1.
    const Mat3 dF =
        svd.U.col(0) * svd.V.col(1).transpose() + svd.U.col(1) * svd.V.col(0).transpose();
    return std::abs(compute_svd_differential(svd, dF, tol).omega_V(0, 1));
  };
  CHECK(coupling(1e-2) == doctest::Approx(1 / 1e-2).epsilon(1e-6));
  CHECK(coupling(1e-3) == doctest::Approx(1 / 1e-3).epsilon(1e-6));
  CHECK(coupling(1e-6) == doctest::Approx(1 / tol).epsilon(1e-3));
  CHECK(coupling(0.0) == doctest::Approx(1 / tol).epsilon(1e-3));
  CHECK(coupling(0.0) <= 1 / tol);
}
