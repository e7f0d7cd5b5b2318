#include "engine/materials/corotational.hpp"

#include <algorithm>

namespace sinew {

namespace {

double twist_denominator(const Vec3& s, int i, int j) {
  return std::max(s(i) + s(j), Corotational::kMinTwistDenominator);
}

}  // namespace

Corotational::Corotational(const MaterialParameters& params)
    : Corotational(lame_parameters(params).mu, lame_parameters(params).lambda) {}

double Corotational::energy(const Mat3& F) const {
  const Vec3 s = compute_rotation_variant_svd(F).S;
  const double tr = s.sum() - 3;
  return m_mu * (s - Vec3::Ones()).squaredNorm() + m_lambda / 2 * tr * tr;
}

Mat3 Corotational::pk1(const Mat3& F) const {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  const Mat3 R = svd.U * svd.V.transpose();
  return 2 * m_mu * (F - R) + m_lambda * (svd.S.sum() - 3) * R;
}

Mat9 Corotational::hessian(const Mat3& F) const {
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  const Mat3 R = svd.U * svd.V.transpose();
  const double tr = svd.S.sum() - 3;
  Mat9 H;
  // Column a: dP for dF = the a-th unit matrix (column-major).
  for (int a = 0; a < 9; ++a) {
    Mat3 dF = Mat3::Zero();
    dF(a % 3, a / 3) = 1;
    const Mat3 M = svd.U.transpose() * dF * svd.V;
    Mat3 omega = Mat3::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j) omega(i, j) = (M(i, j) - M(j, i)) / twist_denominator(svd.S, i, j);
    const Mat3 dR = svd.U * omega * svd.V.transpose();
    const Mat3 dP = 2 * m_mu * (dF - dR) + m_lambda * tr * dR + m_lambda * M.trace() * R;
    H.col(a) = vec9(dP);
  }
  return 0.5 * (H + H.transpose());
}

SvdEigensystem Corotational::eigensystem(const Mat3& F) const {
  SvdEigensystem system{compute_rotation_variant_svd(F)};
  const Vec3& s = system.svd.S;
  const double tr = s.sum() - 3;
  for (int k = 0; k < 3; ++k) {
    const int i = k == 0 ? 1 : 0;
    const int j = k == 2 ? 1 : 2;
    system.twist(k) = 2 * m_mu + (2 * m_lambda * tr - 4 * m_mu) / twist_denominator(s, i, j);
    system.flip(k) = 2 * m_mu;
  }
  system.scaling = m_lambda * Mat3::Ones();
  system.scaling.diagonal().array() += 2 * m_mu;
  return system;
}

}  // namespace sinew
