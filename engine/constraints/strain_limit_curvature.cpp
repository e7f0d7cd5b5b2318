#include "engine/constraints/strain_limit_curvature.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "engine/materials/eigen_projection.hpp"

namespace sinew {
namespace {

// Floors |d| at kCurvatureGap keeping its sign (0 counts as positive).
double floored(double d) { return d < 0 ? std::min(d, -kCurvatureGap) : std::max(d, kCurvatureGap); }

// x-space: dvec(F)/dx = B with B(r + 3c, 3a + r) = dN_a,c.
Eigen::Matrix<double, 9, 12> vec_F_by_x(const Mat43& dN_dX) {
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
  for (int a = 0; a < 4; ++a)
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) B(r + 3 * c, 3 * a + r) = dN_dX(a, c);
  return B;
}

}  // namespace

Mat12 compute_isotropic_strain_limit_curvature(const RotationVariantSvd& svd, int i, bool stretch,
                                               const Mat43& dN_dX) {
  const double sign = stretch ? 1.0 : -1.0;
  Mat9 H = Mat9::Zero();
  for (int j = 0; j < 3; ++j) {
    if (j == i) continue;
    const double twist = sign / floored(svd.S[i] + svd.S[j]);
    const double flip = sign / floored(svd.S[i] - svd.S[j]);
    // vec(U (E_ij -+ E_ji) V^T) / sqrt 2, column-major like F.
    const Mat3 Eij = svd.U.col(i) * svd.V.col(j).transpose(), Eji = svd.U.col(j) * svd.V.col(i).transpose();
    const Mat3 T = (Eij - Eji) / std::sqrt(2.0), L = (Eij + Eji) / std::sqrt(2.0);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> t(T.data()), l(L.data());
    if (twist > 0) H += twist * t * t.transpose();
    if (flip > 0) H += flip * l * l.transpose();
  }
  const Eigen::Matrix<double, 9, 12> B = vec_F_by_x(dN_dX);
  return B.transpose() * H * B;
}

namespace {

// F with its singular values' magnitudes at least a gap apart, the same U and V: where
// two stretches are closer than kCurvatureGap (relative, as the dV coupling's tolerance) the
// curvature is taken where they are kCurvatureGap apart, plus the probe step so that no
// probe swaps the axes' order. Closer, V turns at a rate ~1 / gap and so does the
// (clamped) dV coupling's derivative: the Hessian would grow like 1 / gap.
Mat3 separated_singular_values(const Mat3& F) {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  Vec3 magnitude = svd.S.cwiseAbs();
  const double gap = kCurvatureGap * std::max(magnitude(0), 1.0) + 4 * kCurvatureStep;
  if (magnitude(0) - magnitude(1) >= gap && magnitude(1) - magnitude(2) >= gap) return F;
  magnitude(0) = std::max(magnitude(0), magnitude(1) + gap);
  magnitude(2) = std::max(0.0, std::min(magnitude(2), magnitude(1) - gap));
  const Vec3 S(magnitude(0), magnitude(1), svd.S(2) < 0 ? -magnitude(2) : magnitude(2));
  return svd.U * S.asDiagonal() * svd.V.transpose();
}

}  // namespace

void strain_limit_hessians(const StrainLimitSpec& spec, const Mat3& F_given, const StrainLimitRows& rows,
                           std::array<Mat9, kStrainRowIndexCount>& hessians) {
  const Mat3 F = separated_singular_values(F_given);
  StrainRowMask wanted = 0;
  // A cut (strain_limit.hpp) holds a direction fixed in the material, which its own row at
  // a probe would not: its block is left 0 (Gauss-Newton for the cuts).
  for (int r = 0; r < rows.count; ++r)
    if (rows.row[r].index < kStrainCutFirst) wanted |= StrainRowMask{1} << rows.row[r].index;
  const Mat43 unused = Mat43::Zero();  // only dC/dF is read
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  for (int r = 0; r < rows.count; ++r) hessians[r].setZero();
  // F and its 9 probes, their SVDs in one batch (compute_rotation_variant_svds: the bits of
  // one at a time).
  std::array<Mat3, 10> probes;
  std::array<RotationVariantSvd, 10> svds;
  probes[0] = F;
  for (int e = 0; e < 9; ++e) {
    Mat3 dF = Mat3::Zero();
    dF(e % 3, e / 3) = kCurvatureStep;
    probes[e + 1] = F + dF;
  }
  compute_rotation_variant_svds(probes.data(), svds.data(), 10);
  StrainLimitRows base;  // margin -inf: exactly the wanted rows, whatever their values
  evaluate_strain_limit(spec, svds[0], unused, -kInfinity, wanted, base);
  for (int e = 0; e < 9; ++e) {
    StrainLimitRows plus;
    evaluate_strain_limit(spec, svds[e + 1], unused, -kInfinity, wanted, plus);
    // A row may vanish at a perturbed F (a_ij crossing 1e-12): its column stays 0.
    for (int r = 0, p = 0, b = 0; r < rows.count; ++r) {
      const int k = rows.row[r].index;
      if (k >= kStrainCutFirst) continue;
      while (p < plus.count && plus.row[p].index < k) ++p;
      while (b < base.count && base.row[b].index < k) ++b;
      if (p == plus.count || b == base.count || plus.row[p].index != k || base.row[b].index != k) continue;
      const Mat3 column = (plus.row[p].dF - base.row[b].dF) / kCurvatureStep;
      hessians[r].col(e) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(column.data());
    }
  }
  for (int r = 0; r < rows.count; ++r) hessians[r] = 0.5 * (hessians[r] + hessians[r].transpose()).eval();
}

void compute_strain_limit_curvatures(const StrainLimitSpec& spec, const Mat3& F, const Mat43& dN_dX,
                                     const StrainLimitRows& rows, std::array<Mat12, kStrainRowIndexCount>& out) {
  if (rows.count == 0) return;
  if (spec.mode == StrainLimitMode::Isotropic) {
    const RotationVariantSvd svd = compute_rotation_variant_svd(F);
    for (int r = 0; r < rows.count; ++r)
      out[r] = compute_isotropic_strain_limit_curvature(svd, rows.row[r].index / 6, rows.row[r].index % 2 == 1, dN_dX);
    return;
  }
  std::array<Mat9, kStrainRowIndexCount> hessians;
  strain_limit_hessians(spec, F, rows, hessians);
  const Eigen::Matrix<double, 9, 12> B = vec_F_by_x(dN_dX);
  for (int r = 0; r < rows.count; ++r) out[r] = B.transpose() * project_numerically(-hessians[r]) * B;
}

}  // namespace sinew
