#include "engine/materials/arruda_boyce.hpp"

#include <cmath>
#include <stdexcept>

namespace sinew {

namespace {

constexpr double kC[5] = {1.0 / 2, 1.0 / 20, 11.0 / 1050, 19.0 / 7000, 519.0 / 673750};

}  // namespace

ArrudaBoyce::ArrudaBoyce(const MaterialParameters& params) : m_n(params.arruda_boyce_n) {
  if (!(m_n > 0)) throw std::invalid_argument("arruda_boyce: arruda_boyce_n must be > 0");
  const LameParameters lame = lame_parameters(params);
  const Vec3 at_rest = series(3);
  m_mu = lame.mu / (2 * at_rest(1));
  m_kappa = lame.mu;
  m_lambda = lame.lambda + lame.mu - 4 * m_mu * at_rest(2);
}

Vec3 ArrudaBoyce::series(double Ic) const {
  Vec3 phi = Vec3::Zero();
  for (int i = 1; i <= 5; ++i) {
    const double c = kC[i - 1] / std::pow(m_n, i - 1);
    phi(0) += c * (std::pow(Ic, i) - std::pow(3.0, i));
    phi(1) += c * i * std::pow(Ic, i - 1);
    if (i >= 2) phi(2) += c * i * (i - 1) * std::pow(Ic, i - 2);
  }
  return phi;
}

InvariantTerms ArrudaBoyce::terms(double Ic, double J) const {
  const Vec3 phi = series(Ic);
  InvariantTerms t;
  t.psi = m_mu * phi(0) + m_lambda / 2 * (J - 1) * (J - 1) - m_kappa * (J - 1);
  t.f1 = m_mu * phi(1);
  t.f2 = m_mu * phi(2);
  t.g1 = m_lambda * (J - 1) - m_kappa;
  t.g2 = m_lambda;
  return t;
}

}  // namespace sinew
