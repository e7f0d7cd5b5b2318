#include "engine/materials/stvk.hpp"

namespace sinew {

namespace {

Mat3 green_strain(const Mat3& F) { return 0.5 * (F.transpose() * F - Mat3::Identity()); }

}  // namespace

Stvk::Stvk(const MaterialParameters& params) {
  const LameParameters lame = lame_parameters(params);
  m_mu = lame.mu;
  m_lambda = lame.lambda;
}

double Stvk::energy(const Mat3& F) const {
  const Mat3 E = green_strain(F);
  return m_mu * E.squaredNorm() + m_lambda / 2 * E.trace() * E.trace();
}

Mat3 Stvk::pk1(const Mat3& F) const {
  const Mat3 E = green_strain(F);
  return F * (2 * m_mu * E + m_lambda * E.trace() * Mat3::Identity());
}

Mat9 Stvk::hessian(const Mat3& F) const {
  const Mat3 E = green_strain(F);
  const Mat3 S = 2 * m_mu * E + m_lambda * E.trace() * Mat3::Identity();
  Mat9 H;
  // Column a: dP for dF = the a-th unit matrix (column-major).
  for (int a = 0; a < 9; ++a) {
    Mat3 dF = Mat3::Zero();
    dF(a % 3, a / 3) = 1;
    const Mat3 dE = 0.5 * (dF.transpose() * F + F.transpose() * dF);
    const Mat3 dP = dF * S + F * (2 * m_mu * dE + m_lambda * dE.trace() * Mat3::Identity());
    H.col(a) = vec9(dP);
  }
  return 0.5 * (H + H.transpose());
}

SvdEigensystem Stvk::eigensystem(const Mat3& F) const {
  SvdEigensystem system{compute_rotation_variant_svd(F)};
  const Vec3& s = system.svd.S;
  const double volume = m_lambda / 2 * (s.squaredNorm() - 3);
  for (int k = 0; k < 3; ++k) {
    const int i = k == 0 ? 1 : 0;
    const int j = k == 2 ? 1 : 2;
    const double squares = s(i) * s(i) + s(j) * s(j) - 1;
    system.twist(k) = m_mu * (squares - s(i) * s(j)) + volume;
    system.flip(k) = m_mu * (squares + s(i) * s(j)) + volume;
  }
  system.scaling = m_lambda * s * s.transpose();
  for (int i = 0; i < 3; ++i) system.scaling(i, i) += m_mu * (3 * s(i) * s(i) - 1) + volume;
  return system;
}

}  // namespace sinew
