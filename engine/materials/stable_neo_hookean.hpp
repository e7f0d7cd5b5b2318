#pragma once
// Stable Neo-Hookean, paper 003 eq. 14:
//   Psi = mu/2 (Ic - 3) + lambda/2 (J - alpha)^2 - mu/2 log(Ic + 1)
// Rest stability (P(I) = 0): alpha = 1 + 3 mu / (4 lambda) (the text's garbled
// "1 + mu/lambda - mu/4 lambda" read as 1 + mu/lambda - mu/(4 lambda); papers/README.md).
// Lame reparameterisation (sec. 3.4): mu = 4/3 mu_L, lambda = lambda_L + 5/6 mu_L, so the
// linearisation at F = I is Hooke's law 2 mu_L eps + lambda_L tr(eps) I.
// f(Ic) = mu/2 (Ic - 3) - mu/2 log(Ic + 1), g(J) = lambda/2 (J - alpha)^2; Hessian and its
// closed-form eigensystem from invariant_material.hpp (paper 003, sec. 4). Defined and finite
// for every finite F (Ic + 1 >= 1). Departure: none.
#include "engine/materials/invariant_material.hpp"

namespace sinew {

class StableNeoHookean : public InvariantMaterial {
 public:
  explicit StableNeoHookean(const MaterialParameters& params);
  const char* name() const override { return "stable_neo_hookean"; }
  InvariantTerms terms(double Ic, double J) const override;

  double mu() const { return m_mu; }
  double lambda() const { return m_lambda; }
  double alpha() const { return m_alpha; }

 private:
  double m_mu;
  double m_lambda;
  double m_alpha;
};

}  // namespace sinew
