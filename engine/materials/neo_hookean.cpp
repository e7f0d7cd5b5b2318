#include "engine/materials/neo_hookean.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sinew {

NeoHookean::NeoHookean(const MaterialParameters& params) {
  const LameParameters lame = lame_parameters(params);
  m_mu = lame.mu;
  m_lambda = lame.lambda;
}

bool NeoHookean::is_defined(const Mat3& F) const {
  const double J = F.determinant();
  return std::isfinite(J) && J > 0;
}

InvariantTerms NeoHookean::terms(double Ic, double J) const {
  InvariantTerms t;
  t.psi = J > 0 ? m_mu / 2 * (Ic - 3) - m_mu * std::log(J) + m_lambda / 2 * std::log(J) * std::log(J)
                : std::numeric_limits<double>::infinity();
  t.f1 = m_mu / 2;
  t.f2 = 0;
  // Volume derivatives frozen below kMinJ (header): finite for every J.
  const double Jc = std::max(J, kMinJ);
  const double log_j = std::log(Jc);
  t.g1 = (m_lambda * log_j - m_mu) / Jc;
  t.g2 = (m_mu + m_lambda - m_lambda * log_j) / (Jc * Jc);
  return t;
}

}  // namespace sinew
