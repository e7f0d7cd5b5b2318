#include "engine/materials/stable_neo_hookean.hpp"

#include <cmath>

namespace sinew {

StableNeoHookean::StableNeoHookean(const MaterialParameters& params) {
  const LameParameters lame = lame_parameters(params);
  m_mu = 4.0 / 3.0 * lame.mu;
  m_lambda = lame.lambda + 5.0 / 6.0 * lame.mu;
  m_alpha = 1 + 3 * m_mu / (4 * m_lambda);
}

InvariantTerms StableNeoHookean::terms(double Ic, double J) const {
  const double d = J - m_alpha;
  InvariantTerms t;
  t.psi = m_mu / 2 * (Ic - 3) + m_lambda / 2 * d * d - m_mu / 2 * std::log(Ic + 1);
  t.f1 = m_mu / 2 * (1 - 1 / (Ic + 1));
  t.f2 = m_mu / (2 * (Ic + 1) * (Ic + 1));
  t.g1 = m_lambda * d;
  t.g2 = m_lambda;
  return t;
}

}  // namespace sinew
