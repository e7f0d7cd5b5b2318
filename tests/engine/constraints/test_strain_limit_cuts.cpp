// The pair cuts of the hyperbolic strain limits (engine/constraints/strain_limit.hpp): extra
// rows along the two directions halfway between two principal axes whose stretches nearly
// meet, fixed in the material for their linearisation.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <random>

#include "tests/support/random_rotation.hpp"
#include "engine/constraints/strain_limit.hpp"

using namespace sinew;

namespace {

const double kNoLimit = std::numeric_limits<double>::infinity();

// A rest tet's shape-function gradients (row a: dN_a/dX) and node positions under F.
struct CutTet {
  std::array<Vec3, 4> X{Vec3(0.01, -0.02, 0.0), Vec3(0.11, 0.01, -0.01), Vec3(-0.02, 0.09, 0.02),
                        Vec3(0.03, 0.02, 0.12)};
  Mat43 dN_dX;
  CutTet() {
    Mat3 Dm;
    for (int a = 1; a < 4; ++a) Dm.col(a - 1) = X[a] - X[0];
    dN_dX.bottomRows<3>() = Dm.inverse();
    dN_dX.row(0) = -dN_dX.bottomRows<3>().colwise().sum();
  }
  Mat3 F_of(const std::array<Vec3, 4>& x) const {
    Mat3 F = Mat3::Zero();
    for (int a = 0; a < 4; ++a) F += x[a] * dN_dX.row(a);
    return F;
  }
};

struct CutIndex {
  int p, j, side, sign;
};
CutIndex decode_cut(int k) {
  const int q = k - kStrainCutFirst;
  return {q / 12, q % 12 / 4, q % 4 / 2, q % 2};
}

StrainLimitSpec cut_test_spec() {
  StrainLimitSpec spec;
  spec.smin = Vec3(0.9, 0.8, 0.95);
  spec.smax = Vec3(1.1, 1.3, 1.05);
  return spec;
}

}  // namespace

TEST_CASE("pair cuts: present exactly where two stretches are within the blend gap, never below their axis' row") {
  std::mt19937 rng(31);
  StrainLimitSpec spec = cut_test_spec();
  const double gap = kStrainLimitBlendGap;
  // Pair 0 near; pair 1 near; both; neither; pair 0 just inside and just outside the gap.
  const Vec3 stretches[] = {Vec3(1.03, 1.02, 0.9),  Vec3(1.1, 0.97, 0.96),           Vec3(1.03, 1.02, 1.015),
                            Vec3(1.15, 1.02, 0.9),  Vec3(1.02 + 0.999 * gap, 1.02, 0.9), Vec3(1.02 + 1.001 * gap, 1.02, 0.9)};
  int cuts_seen = 0;
  for (const Vec3& s : stretches) {
    for (int trial = 0; trial < 4; ++trial) {
      spec.frame = test::random_rotation(rng);
      const Mat3 F = test::random_rotation(rng) * s.asDiagonal() * test::random_rotation(rng).transpose();
      const RotationVariantSvd svd = compute_rotation_variant_svd(F);
      const StrainLimitValues v = compute_strain_limit_values(spec, svd);
      for (int k = kStrainCutFirst; k < kStrainRowIndexCount; ++k) {
        CAPTURE(k);
        const CutIndex cut = decode_cut(k);
        const int axis = cut.side == 1 ? cut.p : cut.p + 1;
        const int row = strain_limit_index(axis, cut.j, cut.side);
        const bool near = svd.S(cut.p) - svd.S(cut.p + 1) < gap;
        // Every axis has both limits here: a cut exists where its pair is near and its
        // axis' row does (a_ij > 1e-12, the same blended cosine).
        CHECK(bool(v.present >> k & 1) == (near && bool(v.present >> row & 1)));
        if (!(v.present >> k & 1)) continue;
        ++cuts_seen;
        // s_{p+1} <= |F w| <= s_p: a cut is never below its axis' row.
        CHECK(v.C[k] >= v.C[row] - 1e-15);
        // Its value is the cut held at its own direction (computed as |F w| there).
        CHECK(strain_cut_value(spec, svd, k, strain_cut_direction(svd, k)) == doctest::Approx(v.C[k]).epsilon(1e-12));
      }
    }
  }
  CHECK(cuts_seen > 100);
  // Off, or another mode: no cut at all.
  const Mat3 F = Vec3(1.03, 1.02, 1.015).asDiagonal();
  for (const bool off : {true, false}) {
    StrainLimitSpec other = spec;
    if (off)
      other.pair_cuts = false;
    else
      other.mode = StrainLimitMode::Orthogonal;
    const StrainLimitValues v = compute_strain_limit_values(other, compute_rotation_variant_svd(F));
    CHECK((v.present >> kStrainCutFirst) == 0);
  }
}

TEST_CASE("pair cuts: each row's Jacobian equals finite differences of its cut with the direction held") {
  CutTet tet;
  std::mt19937 rng(37);
  StrainLimitSpec spec = cut_test_spec();
  const Vec3 stretches[] = {Vec3(1.03, 1.02, 0.9), Vec3(1.1, 0.97, 0.96), Vec3(1.03, 1.02, 1.012),
                            Vec3(1.06, 1.045, 0.93)};
  int rows_seen = 0;
  for (const Vec3& s : stretches) {
    spec.frame = test::random_rotation(rng);
    const Mat3 F = test::random_rotation(rng) * s.asDiagonal() * test::random_rotation(rng).transpose();
    std::array<Vec3, 4> x;
    for (int a = 0; a < 4; ++a) x[a] = F * tet.X[a];
    const RotationVariantSvd svd = compute_rotation_variant_svd(tet.F_of(x));
    StrainLimitRows rows;
    evaluate_strain_limit(spec, svd, tet.dN_dX, kNoLimit, 0, rows);
    double worst = 0;
    for (int r = 0; r < rows.count; ++r) {
      const StrainLimitRow& row = rows.row[r];
      if (row.index < kStrainCutFirst) continue;
      ++rows_seen;
      const Vec3 w = strain_cut_direction(svd, row.index);
      const auto cut_at = [&](const std::array<Vec3, 4>& y) {
        return strain_cut_value(spec, compute_rotation_variant_svd(tet.F_of(y)), row.index, w);
      };
      CHECK(row.value == doctest::Approx(cut_at(x)).epsilon(1e-12));
      double previous = 1e300, error = 0;
      for (const double step : {1e-3, 1e-4, 1e-5, 1e-6}) {
        Vec12 fd;
        for (int n = 0; n < 12; ++n) {
          auto plus = x, minus = x;
          plus[n / 3][n % 3] += step;
          minus[n / 3][n % 3] -= step;
          fd[n] = (cut_at(plus) - cut_at(minus)) / (2 * step);
        }
        error = (fd - row.jac).norm() / row.jac.norm();
        CHECK(error < previous);
        previous = error;
      }
      worst = std::max(worst, error);
    }
    MESSAGE("s = " << s.transpose() << ": worst relative FD error of the cuts " << worst);
    // As for the rows (test_strain_limit.cpp): d3C grows like (s - 1) / gap^3 through the
    // blended cosine; the smallest gap here, 0.008 with s - 1 = 0.03, gives d3C ~ 6e4 and
    // ~1e-10 * 6e4 / 6 * sqrt 12 = 3.5e-6 at the smallest step.
    CHECK(worst < 2e-5);
  }
  CHECK(rows_seen > 20);
}

TEST_CASE("pair cuts: a turn of the stretch within the pair's plane is seen by the cuts, missed by the row") {
  // F = diag(1.021, 1.019, 0.95), every axis limited to 1.02 (frame = I), moved by the flip
  // dF = delta (e0 e1^T + e1 e0^T). The pair's 2x2 block [[s0, delta], [delta, s1]] has the
  // largest stretch m + sqrt(g^2 / 4 + delta^2) (mean m = 1.02, gap g = 0.002): at delta =
  // 2 g it grows by 1.56 g (3.1e-3), where its row (d s0 = dF(0, 0) = 0, the cosines'
  // derivative 0 at theta = 0) predicts no change at all. The cut along (e0 + e1) / sqrt 2
  // predicts |F w| at m + delta (s0 + s1) / (2 |F w|), within g^2 / (8 delta) of the largest
  // stretch's new value: it sees the turn the row misses.
  StrainLimitSpec spec;
  spec.smin = Vec3::Zero();
  spec.smax = Vec3::Constant(1.02);
  const double g = 0.002, delta = 2 * g;
  const Mat3 F = Vec3(1.02 + g / 2, 1.02 - g / 2, 0.95).asDiagonal();
  Mat3 dF = Mat3::Zero();
  dF(0, 1) = dF(1, 0) = delta;
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  StrainLimitRows rows;
  evaluate_strain_limit(spec, svd, Mat43::Zero(), kNoLimit, 0, rows);
  const StrainLimitValues moved = compute_strain_limit_values(spec, compute_rotation_variant_svd(F + dF));
  const auto predicted = [&](const StrainLimitRow& row) { return row.value + (row.dF.array() * dF.array()).sum(); };
  double row_prediction = kNoLimit, cut_prediction = kNoLimit, truth = kNoLimit;
  for (int r = 0; r < rows.count; ++r) {
    const int k = rows.row[r].index;
    if (k < kStrainCutFirst && k / 6 == 0 && k % 2 == 1) {  // the stretch rows of axis 0
      row_prediction = std::min(row_prediction, predicted(rows.row[r]));
      truth = std::min(truth, moved.C[k]);
    }
    if (k >= kStrainCutFirst && decode_cut(k).p == 0 && decode_cut(k).side == 1)
      cut_prediction = std::min(cut_prediction, predicted(rows.row[r]));
  }
  const double growth = std::sqrt(g * g / 4 + delta * delta) - g / 2;  // of the largest stretch
  MESSAGE("the largest stretch grows by " << growth << "; ");
  MESSAGE("largest stretch's row of axis 0 after the flip: " << truth << ", predicted by its rows " << row_prediction
                                                          << ", by the cuts " << cut_prediction);
  // The row misses the growth but for the part the cosines' turn takes off (the blend
  // weight falls as the gap opens to 2 sqrt(g^2 / 4 + delta^2)): more than the solver's
  // strain tolerance, 1e-3, so a QP trusting it would end past its limit.
  CHECK(row_prediction - truth > 1e-3);
  // The cuts predict at least as much violation, up to g^2 / (8 delta) and |F w|'s own
  // second order, delta^2 / |F w| (they predict more: the row's cosine a_00 falls from 1 to
  // 0.93 with the turn, which the truth has and the cuts' first order does not).
  CHECK(cut_prediction <= truth + g * g / (8 * delta) + delta * delta);
}
