#include "engine/materials/fung.hpp"

#include <cmath>
#include <stdexcept>

namespace sinew {

Fung::Fung(const MaterialParameters& params) : m_c(params.fung_c) {
  if (!(m_c > 0)) throw std::invalid_argument("fung: fung_c must be > 0");
  const LameParameters lame = lame_parameters(params);
  m_mu = lame.mu;
  m_kappa = lame.mu;
  m_lambda = lame.lambda + (1 - 2 * m_c) * lame.mu;
}

InvariantTerms Fung::terms(double Ic, double J) const {
  // e0, e1, e2: exp(x) and its first two derivatives (Taylor-continued past kMaxExponent).
  const double x = m_c * (Ic - 3);
  double e0, e1, e2;
  if (x <= kMaxExponent) {
    e0 = e1 = e2 = std::exp(x);
  } else {
    const double top = std::exp(kMaxExponent), d = x - kMaxExponent;
    e0 = top * (1 + d + d * d / 2);
    e1 = top * (1 + d);
    e2 = top;
  }
  InvariantTerms t;
  t.psi = m_mu / (2 * m_c) * (e0 - 1) + m_lambda / 2 * (J - 1) * (J - 1) - m_kappa * (J - 1);
  t.f1 = m_mu / 2 * e1;
  t.f2 = m_mu * m_c / 2 * e2;
  t.g1 = m_lambda * (J - 1) - m_kappa;
  t.g2 = m_lambda;
  return t;
}

}  // namespace sinew
