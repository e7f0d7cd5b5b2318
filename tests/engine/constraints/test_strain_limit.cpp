#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "tests/support/random_rotation.hpp"
#include "engine/constraints/strain_limit.hpp"

using namespace sinew;

namespace {

const double kInf = std::numeric_limits<double>::infinity();
const StrainLimitMode kModes[] = {StrainLimitMode::Hyperbolic, StrainLimitMode::Orthogonal,
                                  StrainLimitMode::Linear, StrainLimitMode::Isotropic};

const char* mode_name(StrainLimitMode m) {
  switch (m) {
    case StrainLimitMode::Hyperbolic:
      return "hyperbolic";
    case StrainLimitMode::Orthogonal:
      return "orthogonal";
    case StrainLimitMode::Linear:
      return "linear";
    case StrainLimitMode::Isotropic:
      return "isotropic";
  }
  return "";
}

// A rest tet: nodes X_0..X_3, and the gradients of its shape functions (row a: dN_a/dX), from
// F = Ds Dm^-1 = sum_{a=1..3} (x_a - x_0) (row a-1 of Dm^-1).
struct Tet {
  std::array<Vec3, 4> X{Vec3(0.01, -0.02, 0.0), Vec3(0.11, 0.01, -0.01), Vec3(-0.02, 0.09, 0.02),
                        Vec3(0.03, 0.02, 0.12)};
  Mat43 dN_dX;
  Tet() {
    Mat3 Dm;
    for (int a = 1; a < 4; ++a) Dm.col(a - 1) = X[a] - X[0];
    const Mat3 Dm_inv = Dm.inverse();
    dN_dX.bottomRows<3>() = Dm_inv;
    dN_dX.row(0) = -Dm_inv.colwise().sum();
  }
  std::array<Vec3, 4> deformed(const Mat3& F) const {
    std::array<Vec3, 4> x;
    for (int a = 0; a < 4; ++a) x[a] = F * X[a] + Vec3(0.3, -0.1, 0.2);
    return x;
  }
  Mat3 F_of(const std::array<Vec3, 4>& x) const {
    Mat3 F = Mat3::Zero();
    for (int a = 0; a < 4; ++a) F += x[a] * dN_dX.row(a);
    return F;
  }
};

StrainLimitValues values(const StrainLimitSpec& spec, const Mat3& F) {
  return compute_strain_limit_values(spec, compute_rotation_variant_svd(F));
}

// Central-difference gradient of constraint k over the 12 node coordinates.
Vec12 fd_gradient(const Tet& tet, const StrainLimitSpec& spec, const std::array<Vec3, 4>& x, int k,
                  double step) {
  Vec12 g;
  for (int n = 0; n < 12; ++n) {
    auto xp = x, xm = x;
    xp[n / 3][n % 3] += step;
    xm[n / 3][n % 3] -= step;
    const StrainLimitValues p = values(spec, tet.F_of(xp)), m = values(spec, tet.F_of(xm));
    REQUIRE((p.present >> k & 1u));
    REQUIRE((m.present >> k & 1u));
    g[n] = (p.C[k] - m.C[k]) / (2 * step);
  }
  return g;
}

int popcount(StrainRowMask bits) {
  int n = 0;
  for (; bits; bits &= bits - 1) ++n;
  return n;
}

}  // namespace

TEST_CASE("strain limit: every mode's Jacobian equals finite differences of its value") {
  Tet tet;
  std::mt19937 rng(17);
  StrainLimitSpec spec;
  spec.smin = Vec3(0.9, 0.8, 0.95);
  spec.smax = Vec3(1.1, 1.3, 1.05);
  // Singular values apart by far more than kStrainLimitGapTolerance; one inverted case; two
  // within kStrainLimitBlendGap of each other (hyperbolic: blended cosines), one with all
  // three within it.
  const Vec3 stretches[] = {Vec3(1.15, 1.02, 0.9), Vec3(1.3, 0.95, 0.8), Vec3(1.1, 0.97, -0.85),
                            Vec3(1.03, 1.02, 0.9), Vec3(1.03, 1.02, 1.015)};
  // The paper's rows: the pair cuts hold a direction fixed in the material, so their
  // Jacobians are not those of their values as functions of F (test_strain_limit_cuts.cpp).
  spec.pair_cuts = false;
  for (StrainLimitMode mode : kModes) {
    spec.mode = mode;
    for (const Vec3& s : stretches) {
      spec.frame = test::random_rotation(rng);
      const Mat3 F = test::random_rotation(rng) * s.asDiagonal() * test::random_rotation(rng).transpose();
      const auto x = tet.deformed(F);
      StrainLimitRows rows;
      evaluate_strain_limit(spec, tet.F_of(x), tet.dN_dX, kInf, 0, rows);
      const bool per_axis =
          mode == StrainLimitMode::Hyperbolic || mode == StrainLimitMode::Orthogonal;
      CHECK(rows.count == (per_axis ? 18 : 6));
      double worst_error = 0;
      for (int r = 0; r < rows.count; ++r) {
        const StrainLimitRow& row = rows.row[r];
        REQUIRE(row.jac.allFinite());
        CHECK(row.value == doctest::Approx(values(spec, F).C[row.index]).epsilon(1e-12));
        // Central differences: the error falls like step^2 until rounding takes over.
        double previous = 1e300, error = 0;
        for (double step : {1e-3, 1e-4, 1e-5, 1e-6}) {
          error = (fd_gradient(tet, spec, x, row.index, step) - row.jac).norm() / row.jac.norm();
          CHECK(error < previous);
          previous = error;
        }
        worst_error = std::max(worst_error, error);
      }
      MESSAGE(std::string(mode_name(mode))
              << ", s = " << s.transpose() << ": worst relative FD error " << worst_error);
      // The central differences' own error is ~ step^2 |d3C| / 6, and d3C grows like
      // (s - 1) / gap^3 where stretches are a gap apart: 1e-6 for gaps of 0.1 or more; for
      // the smallest gap tested, 0.005, d3C ~ 0.03 / 1.25e-7 = 2.4e5 and the smallest step
      // moves F by ~1e-5, so ~1e-10 * 2.4e5 / 6 = 4e-6 per coordinate, 1.4e-5 over the 12
      // (a norm: sqrt 12): 2e-5.
      const double gap = std::min(std::abs(s(0) - s(1)), std::abs(s(1) - s(2)));
      CHECK(worst_error < (gap >= 0.1 ? 1e-6 : 2e-5));
    }
  }
}

TEST_CASE("strain limit: a free axis produces no constraint; no limits, no rows") {
  Tet tet;
  std::mt19937 rng(4);
  const Mat3 F =
      test::random_rotation(rng) * Vec3(1.2, 1.0, 0.9).asDiagonal() * test::random_rotation(rng).transpose();
  StrainLimitSpec spec;  // defaults: smin = 0, smax = +inf on every axis: all free
  for (StrainLimitMode mode : kModes) {
    spec.mode = mode;
    CHECK(values(spec, F).present == 0);
    CHECK(worst_strain_violation(spec, F) == -kInf);
    StrainLimitRows rows;
    evaluate_strain_limit(spec, F, tet.dN_dX, kInf, ~0u, rows);
    CHECK(rows.count == 0);
  }
  // Only axis 0 limited: hyperbolic and orthogonal have the 6 constraints of j = 0.
  spec.smin = Vec3(0.95, 0, -1);
  spec.smax = Vec3(1.05, kInf, kInf);
  for (StrainLimitMode mode : {StrainLimitMode::Hyperbolic, StrainLimitMode::Orthogonal}) {
    spec.mode = mode;
    const StrainLimitValues v = values(spec, F);
    CHECK(popcount(v.present) == 6);
    for (int i = 0; i < 3; ++i)
      for (int side = 0; side < 2; ++side)
        CHECK((v.present >> strain_limit_index(i, 0, side) & 1u));
  }
  // Hyperbolic with F = diag: only the principal axis along e_0 has limits (a = 1); the
  // others are orthogonal to it (a = 0: infinite projected limit, no constraint).
  spec.mode = StrainLimitMode::Hyperbolic;
  const StrainLimitValues diag = values(spec, Vec3(1.01, 1.2, 0.9).asDiagonal());
  CHECK(popcount(diag.present) == 2);
  // Linear: the stretch limit is infinite as soon as a principal axis leans on a free axis.
  spec.mode = StrainLimitMode::Linear;
  const StrainLimitValues lin = values(spec, F);
  for (int i = 0; i < 3; ++i) {
    CHECK((lin.present >> strain_limit_index(i, 0, 0) & 1u));
    CHECK_FALSE((lin.present >> strain_limit_index(i, 0, 1) & 1u));
  }
}

TEST_CASE("strain limit: with frame = I and F = diag(s) the projected limits are the axis limits") {
  // The SVD sorts by magnitude: s = (1.05, 0.97, 1.01) gives principal axes e_0, e_2, e_1.
  // Stretches kStrainLimitBlendGap or more apart: the hyperbolic cosines are the paper's.
  StrainLimitSpec spec;
  spec.smin = Vec3(0.9, 0.8, 0.95);
  spec.smax = Vec3(1.1, 1.3, 1.05);
  const RotationVariantSvd svd = compute_rotation_variant_svd(Vec3(1.05, 0.97, 1.01).asDiagonal());
  const int axis_of[3] = {0, 2, 1};
  for (StrainLimitMode mode : {StrainLimitMode::Hyperbolic, StrainLimitMode::Linear}) {
    spec.mode = mode;
    const ProjectedStrainLimits lim = compute_projected_strain_limits(spec, svd);
    for (int i = 0; i < 3; ++i) {
      CHECK(lim.smin(i) == doctest::Approx(spec.smin(axis_of[i])).epsilon(1e-12));
      CHECK(lim.smax(i) == doctest::Approx(spec.smax(axis_of[i])).epsilon(1e-12));
    }
  }
  // Orthogonal projection gives each principal axis the limit 1 from the two axes it is
  // orthogonal to (eqs. 19-20 with |cos| = 0): no deformation allowed at all (paper, sec. 5.2).
  spec.mode = StrainLimitMode::Orthogonal;
  const ProjectedStrainLimits ortho = compute_projected_strain_limits(spec, svd);
  CHECK((ortho.smin - Vec3::Ones()).norm() < 1e-15);
  CHECK((ortho.smax - Vec3::Ones()).norm() < 1e-15);
  // Isotropic: the tightest of the axis limits, 0.95 and 1.05, on every axis.
  spec.mode = StrainLimitMode::Isotropic;
  const ProjectedStrainLimits iso = compute_projected_strain_limits(spec, svd);
  CHECK((iso.smin - Vec3::Constant(0.95)).norm() < 1e-15);
  CHECK((iso.smax - Vec3::Constant(1.05)).norm() < 1e-15);
}

TEST_CASE("strain limit: the projected limits match the constraints' signs") {
  // All C >= 0 exactly when smin(i) <= s_i <= smax(i), for every mode.
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0.85, 1.15);
  StrainLimitSpec spec;
  spec.smin = Vec3(0.9, 0.0, 0.95);
  spec.smax = Vec3(1.1, 1.3, kInf);
  for (StrainLimitMode mode : kModes) {
    spec.mode = mode;
    for (int trial = 0; trial < 200; ++trial) {
      spec.frame = test::random_rotation(rng);
      const Mat3 F = test::random_rotation(rng) * Vec3(u(rng), u(rng), u(rng)).asDiagonal() *
                     test::random_rotation(rng).transpose();
      const RotationVariantSvd svd = compute_rotation_variant_svd(F);
      const ProjectedStrainLimits lim = compute_projected_strain_limits(spec, svd);
      const bool inside =
          (svd.S.array() >= lim.smin.array()).all() && (svd.S.array() <= lim.smax.array()).all();
      CHECK(inside == (worst_strain_violation(spec, F) <= 0));
    }
  }
}

TEST_CASE("strain limit: isotropic limits are rotation-invariant") {
  std::mt19937 rng(12);
  StrainLimitSpec spec;
  spec.mode = StrainLimitMode::Isotropic;
  spec.smin = Vec3::Constant(0.96);
  spec.smax = Vec3::Constant(1.04);
  const Mat3 F =
      test::random_rotation(rng) * Vec3(1.07, 1.0, 0.93).asDiagonal() * test::random_rotation(rng).transpose();
  const StrainLimitValues base = values(spec, F);
  for (int trial = 0; trial < 10; ++trial) {
    StrainLimitSpec turned = spec;
    turned.frame = test::random_rotation(rng);  // unused by the isotropic mode
    const Mat3 G = test::random_rotation(rng) * F * test::random_rotation(rng).transpose();
    const StrainLimitValues v = values(turned, G);
    REQUIRE(v.present == base.present);
    for (int k = 0; k < kStrainLimitCount; ++k)
      if (base.present >> k & 1u) CHECK(v.C[k] == doctest::Approx(base.C[k]).epsilon(1e-12));
  }
}

TEST_CASE("strain limit: material-frame limits follow the material") {
  // Rotating the rest shape by Q (F -> F Q^T) together with the frame (M -> Q M), and the
  // world by R (F -> R F), leaves every constraint of every mode unchanged.
  std::mt19937 rng(13);
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0.0, 0.75);
  spec.smax = Vec3(1.05, kInf, 1.25);
  for (StrainLimitMode mode : kModes) {
    spec.mode = mode;
    spec.frame = test::random_rotation(rng);
    const Mat3 F =
        test::random_rotation(rng) * Vec3(1.1, 0.98, 0.8).asDiagonal() * test::random_rotation(rng).transpose();
    const StrainLimitValues base = values(spec, F);
    for (int trial = 0; trial < 5; ++trial) {
      const Mat3 Q = test::random_rotation(rng), R = test::random_rotation(rng);
      StrainLimitSpec turned = spec;
      turned.frame = Q * spec.frame;
      const StrainLimitValues v = values(turned, R * F * Q.transpose());
      REQUIRE(v.present == base.present);
      for (int k = 0; k < kStrainLimitCount; ++k)
        if (base.present >> k & 1u) CHECK(v.C[k] == doctest::Approx(base.C[k]).epsilon(1e-10));
      // Rotating only the frame changes the anisotropic constraints.
      if (mode != StrainLimitMode::Isotropic && trial == 0) {
        const StrainLimitValues moved = values(turned, F);
        double change = 0;
        for (int k = 0; k < kStrainLimitCount; ++k)
          if ((moved.present & base.present) >> k & 1u)
            change = std::max(change, std::abs(moved.C[k] - base.C[k]));
        CHECK(change > 1e-3);
      }
    }
  }
}

TEST_CASE("strain limit: hyperbolic vs orthogonal vs linear on a principal axis at 45 degrees") {
  // Axis x limited to [0.95, 1.05], y and z free. The principal axes are
  //   d = (1, 1, 0)/sqrt2 stretched by 1.05, p = (1, -1, 0)/sqrt2 by 1.00, z by 0.96,
  // so |cos| = 1/sqrt2 between d (and p) and x, and 0 between z and x (the stretches are
  // kStrainLimitBlendGap or more apart: the hyperbolic cosines are the paper's).
  // x-fibre: F e_x = (1.05 d + 1.00 p)/sqrt2 = (1.025, 0.025, 0), |F e_x| = 1.025305: the
  // material is inside its x-limit (to first order the fibre strain is 0.05 cos^2 = 0.025).
  //   hyperbolic (eqs. 7-8): d gets 1 +- 0.05 sqrt2 = [0.929289, 1.070711]: satisfied,
  //     C_max(d, x) = 0.05 - 0.05/sqrt2 = 0.014645; z gets no limit (|cos| = 0).
  //   orthogonal (eqs. 19-20): d gets 1 +- 0.05/sqrt2 = [0.964645, 1.035355]: violated,
  //     C_max(d, x) = 0.05/sqrt2 - 0.05 = -0.014645; z gets [1, 1]: C_min(z, x) = -0.04.
  //   linear (eqs. 21-22): d gets compress 0.95/sqrt2 = 0.671751 (free y counts 0) and no
  //     stretch limit (d leans on the free y axis): under-constrained.
  const double r2 = std::sqrt(0.5);
  const Vec3 d(r2, r2, 0), p(r2, -r2, 0), z(0, 0, 1);
  const Mat3 F = 1.05 * d * d.transpose() + 1.00 * p * p.transpose() + 0.96 * z * z.transpose();
  CHECK((F * Vec3::UnitX()).norm() == doctest::Approx(1.025305).epsilon(1e-6));
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0, 0);
  spec.smax = Vec3(1.05, kInf, kInf);
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  REQUIRE(std::abs(svd.V.col(0).dot(d)) == doctest::Approx(1).epsilon(1e-12));
  REQUIRE(std::abs(svd.V.col(2).dot(z)) == doctest::Approx(1).epsilon(1e-12));

  spec.mode = StrainLimitMode::Hyperbolic;
  ProjectedStrainLimits lim = compute_projected_strain_limits(spec, svd);
  CHECK(lim.smin(0) == doctest::Approx(1 - 0.05 / r2).epsilon(1e-12));
  CHECK(lim.smax(0) == doctest::Approx(1 + 0.05 / r2).epsilon(1e-12));
  CHECK(lim.smax(1) == doctest::Approx(1 + 0.05 / r2).epsilon(1e-12));
  CHECK(lim.smin(2) == -kInf);
  CHECK(lim.smax(2) == kInf);
  StrainLimitValues v = compute_strain_limit_values(spec, svd);
  CHECK(v.C[strain_limit_index(0, 0, 1)] == doctest::Approx(0.05 - 0.05 * r2).epsilon(1e-12));
  CHECK(worst_strain_violation(spec, F) < 0);

  spec.mode = StrainLimitMode::Orthogonal;
  lim = compute_projected_strain_limits(spec, svd);
  CHECK(lim.smin(0) == doctest::Approx(1 - 0.05 * r2).epsilon(1e-12));
  CHECK(lim.smax(0) == doctest::Approx(1 + 0.05 * r2).epsilon(1e-12));
  CHECK(lim.smin(2) == doctest::Approx(1).epsilon(1e-12));
  CHECK(lim.smax(2) == doctest::Approx(1).epsilon(1e-12));
  v = compute_strain_limit_values(spec, svd);
  CHECK(v.C[strain_limit_index(0, 0, 1)] == doctest::Approx(0.05 * r2 - 0.05).epsilon(1e-12));
  CHECK(v.C[strain_limit_index(2, 0, 0)] == doctest::Approx(-0.04).epsilon(1e-12));
  CHECK(worst_strain_violation(spec, F) == doctest::Approx(0.04).epsilon(1e-12));

  spec.mode = StrainLimitMode::Linear;
  lim = compute_projected_strain_limits(spec, svd);
  CHECK(lim.smin(0) == doctest::Approx(0.95 * r2).epsilon(1e-12));
  CHECK(lim.smax(0) == kInf);
}

TEST_CASE("strain limit: the paper's vertical beam freezes under orthogonal projection") {
  // Sec. 5.2: x limited to [0.95, 1.05], y (vertical) and z free; the beam sags: F = diag(1.01,
  // 0.9, 1.03), principal axes aligned with the global ones. Hyperbolic: only x is limited,
  // C = (0.06, 0.04), worst -0.04. Orthogonal: y and z get [1, 1], so the 10 % compression
  // already violates by 0.1.
  const Mat3 F = Vec3(1.01, 0.9, 1.03).asDiagonal();
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0, 0);
  spec.smax = Vec3(1.05, kInf, kInf);
  spec.mode = StrainLimitMode::Hyperbolic;
  CHECK(worst_strain_violation(spec, F) == doctest::Approx(-0.04).epsilon(1e-12));
  spec.mode = StrainLimitMode::Orthogonal;
  CHECK(worst_strain_violation(spec, F) == doctest::Approx(0.1).epsilon(1e-12));
}

TEST_CASE("strain limit: only near-active rows, plus the kept ones, are returned") {
  Tet tet;
  StrainLimitSpec spec;
  spec.smin = Vec3(0.9, 0.8, 0.95);
  spec.smax = Vec3(1.1, 1.3, 1.05);
  std::mt19937 rng(2);
  spec.frame = test::random_rotation(rng);
  const Mat3 F =
      test::random_rotation(rng) * Vec3(1.08, 1.0, 0.93).asDiagonal() * test::random_rotation(rng).transpose();
  const StrainLimitValues v = values(spec, F);
  const double margin = 0.02;
  const StrainRowMask keep = StrainRowMask{1} << strain_limit_index(1, 1, 1);
  StrainLimitRows rows;
  evaluate_strain_limit(spec, F, tet.dN_dX, margin, keep, rows);
  StrainRowMask expected = 0;
  for (int k = 0; k < kStrainRowIndexCount; ++k)
    if ((v.present >> k & 1u) && (v.C[k] < margin || (keep >> k & 1u))) expected |= StrainRowMask{1} << k;
  StrainRowMask got = 0;
  for (int r = 0; r < rows.count; ++r) {
    got |= StrainRowMask{1} << rows.row[r].index;
    CHECK(rows.row[r].value == v.C[rows.row[r].index]);
    if (r > 0) CHECK(rows.row[r].index > rows.row[r - 1].index);
  }
  CHECK(got == expected);
  CHECK(popcount(expected) > 1);
  CHECK(popcount(expected) < popcount(v.present));
}

TEST_CASE("strain limit: rows stay finite at rest, at repeated and at zero singular values") {
  // Behaviour: values are exact everywhere; the Jacobian's dV part uses the clamped coupling
  // of svd_derivative.hpp with gap kStrainLimitGapTolerance = 1e-3, so |dV/dF(r, c)| entries
  // are at most 2 / eps and each row is bounded by
  //   |dC/dF(r, c)| <= |p| + |dV e_i| |M q| <= 1 + sqrt(6) (2 / eps) |q|.
  // At rest the hyperbolic Jacobian has q = (s_i - 1) sign = 0: exactly a_ij u_i v_i^T.
  Tet tet;
  std::mt19937 rng(6);
  const Mat3 Q1 = test::random_rotation(rng), Q2 = test::random_rotation(rng);
  const Mat3 cases[] = {
      Mat3::Identity(),
      Q1 * Vec3(1.03, 1.03, 0.98).asDiagonal() * Q2.transpose(),
      Q1 * Vec3(1.03, 1.03 - 1e-9, 0.98).asDiagonal() * Q2.transpose(),
      Q1 * Vec3(0.97, 0.97, 0.97).asDiagonal() * Q2.transpose(),
      Q1 * Vec3(1.0, 0.0, 0.0).asDiagonal() * Q2.transpose(),
      Q1 * Vec3(1.0, 0.5, -0.5).asDiagonal() * Q2.transpose(),
      Mat3::Zero(),
  };
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0.75, 0.98);
  spec.smax = Vec3(1.05, 1.25, 1.02);
  spec.frame = test::random_rotation(rng);
  const double eps = kStrainLimitGapTolerance * 1.03;
  for (StrainLimitMode mode : kModes) {
    spec.mode = mode;
    for (const Mat3& F : cases) {
      StrainLimitRows rows;
      evaluate_strain_limit(spec, F, tet.dN_dX, kInf, 0, rows);
      CHECK(rows.count > 0);
      CHECK(std::isfinite(worst_strain_violation(spec, F)));
      const double q_max = 1.25 * 1.25 / 0.5 + 2;  // a generous bound on |q| for these cases
      const double bound = (1 + std::sqrt(6.0) * 2 / eps * q_max) * 3 * tet.dN_dX.norm();
      for (int r = 0; r < rows.count; ++r) {
        REQUIRE(std::isfinite(rows.row[r].value));
        REQUIRE(rows.row[r].jac.allFinite());
        CHECK(rows.row[r].jac.norm() <= bound);
      }
    }
  }
  // At rest, hyperbolic: the three stretches are equal, so every blended cosine is the
  // length of m_j, a_ij = 1 (all 18 rows), and dC/dx_a = +-(u_i v_i^T) dN_a: s_i - 1 = 0
  // removes every rotation and blend term. Both pairs are equal too: 24 cuts (2 pairs, 3
  // axes, 2 sides, 2 directions), each +-(n w^T) dN_a with n = w (|F w| - 1 = 0).
  spec.mode = StrainLimitMode::Hyperbolic;
  const RotationVariantSvd rest = compute_rotation_variant_svd(Mat3::Identity());
  StrainLimitRows rows;
  evaluate_strain_limit(spec, Mat3::Identity(), tet.dN_dX, kInf, 0, rows);
  CHECK(rows.count == 18 + 24);
  for (int r = 0; r < rows.count; ++r) {
    const int k = rows.row[r].index;
    Mat3 G;
    if (k < kStrainCutFirst) {
      const int i = k / 6;
      const double sign = k % 2 == 0 ? 1.0 : -1.0;
      G = sign * rest.U.col(i) * rest.V.col(i).transpose();
    } else {
      const bool stretch = (k - kStrainCutFirst) % 4 / 2 == 1;
      const Vec3 w = strain_cut_direction(rest, k);
      G = (stretch ? -1.0 : 1.0) * w * w.transpose();
    }
    for (int a = 0; a < 4; ++a)
      CHECK((rows.row[r].jac.segment<3>(3 * a) - G * tet.dN_dX.row(a).transpose()).norm() < 1e-12);
  }
}

TEST_CASE("strain limit: hyperbolic limits are continuous where principal stretches meet") {
  // Two equal stretches 1.027 in a plane holding m_2 (limits 0.98-1.02 on it): any pair of
  // axes in that plane is a valid SVD, and the paper's |c_i2| could be anything in [0, 1]
  // for the pair the SVD happens to return. With the blended cosine (strain_limit.hpp) the
  // pair's a_i2 is 1 whatever the pair: C_max = 0.02 - 0.027, the fibre's own strain past
  // its limit; and F moved by 1e-9 moves every C by at most 1e-9 times its Jacobian's
  // size (a few units here), where the unblended cosines may jump by O(0.01).
  std::mt19937 rng(21);
  StrainLimitSpec spec;
  spec.smin = Vec3(0.95, 0.75, 0.98);
  spec.smax = Vec3(1.05, 1.25, 1.02);
  const Mat3 R = test::random_rotation(rng);
  // Rest axes: m_0 alone (stretch 0.99), the plane of m_1 and m_2 (stretch 1.027).
  const Mat3 F = R * (0.99 * Vec3::UnitX() * Vec3::UnitX().transpose() +
                      1.027 * (Mat3::Identity() - Vec3::UnitX() * Vec3::UnitX().transpose()));
  CHECK(worst_strain_violation(spec, F) == doctest::Approx(0.007).epsilon(1e-9));
  const StrainLimitValues base = values(spec, F);
  std::normal_distribution<double> n(0, 1e-9);
  double largest_change = 0;
  for (int trial = 0; trial < 50; ++trial) {
    Mat3 dF;
    for (int e = 0; e < 9; ++e) dF(e % 3, e / 3) = n(rng);
    const StrainLimitValues moved = values(spec, F + dF);
    // Rows with a_ij ~ 1e-9 may come and go (no constraint where a_ij <= 1e-12): those
    // present in both are compared, and the rows of the equal pair are always present.
    for (int i : {0, 1})  // the SVD sorts the stretches: 1.027, 1.027, 0.99
      CHECK((moved.present >> strain_limit_index(i, 2, 1) & 1u));
    for (int k = 0; k < kStrainLimitCount; ++k)
      if ((base.present & moved.present) >> k & 1u) largest_change = std::max(largest_change, std::abs(moved.C[k] - base.C[k]));
  }
  MESSAGE("largest change of a constraint under 1e-9 perturbations of F: " << largest_change);
  CHECK(largest_change < 1e-7);
}

TEST_CASE("strain limit: the values alone equal the rows' values bit for bit, in every mode") {
  // compute_strain_limit_values has a path of its own for hyperbolic limits (every row build
  // evaluates every limited tet); the rows come from the derivative path. Near-equal
  // stretches (the blend), free axes, compression and a rotated material frame included.
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, 1);
  const Tet tet;
  int compared = 0;
  bool absent_seen = false;  // a hyperbolic case with constraints left out (a_ij <= 1e-12)
  for (int trial = 0; trial < 400; ++trial) {
    StrainLimitSpec spec;
    spec.mode = kModes[trial % 4];
    spec.frame = trial % 3 == 0 ? Mat3::Identity() : test::random_rotation(rng);
    spec.smin = Vec3(0.95, trial % 5 == 0 ? 0.0 : 0.75, 0.98);
    spec.smax = Vec3(1.05, 1.25, trial % 7 == 0 ? kInf : 1.02);
    // Stretches up to ~5 % apart, and every fourth trial two of them within the 2 % blend gap.
    Vec3 s(1 + 0.04 * n(rng), 1 + 0.04 * n(rng), 1 + 0.04 * n(rng));
    if (trial % 4 == 1) s(1) = s(0) + 0.005 * n(rng);
    // Every 25th: principal axes along the material axes, stretches apart by more than the
    // blend gap, so that a_ij = 0 for i != j and those constraints are absent.
    const bool aligned = trial % 25 == 0;
    if (aligned) {
      spec.frame = Mat3::Identity();
      s = Vec3(1.1, 1.0, 0.9);
    }
    const Mat3 F = aligned ? Mat3(s.asDiagonal()) : Mat3(test::random_rotation(rng) * s.asDiagonal() * test::random_rotation(rng));
    const RotationVariantSvd svd = compute_rotation_variant_svd(F);
    const StrainLimitValues v = compute_strain_limit_values(spec, svd);
    StrainLimitRows rows;
    evaluate_strain_limit_rows(spec, svd, tet.dN_dX, kInf, 0u, rows);  // margin +inf: every constraint
    StrainRowMask present = 0;
    for (int r = 0; r < rows.count; ++r) {
      const int k = rows.row[r].index;
      present |= StrainRowMask{1} << k;
      CHECK(std::memcmp(&v.C[k], &rows.row[r].value, sizeof(double)) == 0);
      ++compared;
    }
    CHECK(present == v.present);
    if (aligned && spec.mode == StrainLimitMode::Hyperbolic) CHECK(__builtin_popcountll(v.present) <= 6);
    absent_seen = absent_seen || (aligned && spec.mode == StrainLimitMode::Hyperbolic);
  }
  CHECK(compared > 2000);
  CHECK(absent_seen);
}
