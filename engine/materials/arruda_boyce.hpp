#pragma once
// Arruda-Boyce (eight-chain) elasticity, the extension of paper 003 sec. 7. The extracted text
// stops before sec. 7, so this is the standard five-term series of Arruda and Boyce (1993) in
// the first invariant, plus the paper's rest-stable volume term (eqs. 11-13):
//   Psi = mu sum_{i=1..5} C_i / N^(i-1) (Ic^i - 3^i) + lambda/2 (J - 1)^2 - kappa (J - 1)
//   C = (1/2, 1/20, 11/1050, 19/7000, 519/673750),  N = MaterialParameters::arruda_boyce_n > 0
// (N -> infinity gives mu/2 (Ic - 3)). The volume term equals lambda/2 (J - alpha)^2,
// alpha = 1 + kappa/lambda, up to a constant (Psi(I) = 0; lambda <= 0 allowed).
// Constants (P(I) = 0 and Hooke at F = I; phi = the series without mu):
//   mu = mu_L / (2 phi'(3)), kappa = mu_L, lambda = lambda_L + mu_L - 4 mu phi''(3).
// Hessian and eigensystem: invariant_material.hpp. A polynomial: finite for every finite F.
// Departure: none beyond the choice of form.
#include "engine/materials/invariant_material.hpp"

namespace sinew {

class ArrudaBoyce : public InvariantMaterial {
 public:
  // Throws std::invalid_argument unless arruda_boyce_n > 0.
  explicit ArrudaBoyce(const MaterialParameters& params);
  const char* name() const override { return "arruda_boyce"; }
  InvariantTerms terms(double Ic, double J) const override;

 private:
  // phi(Ic), phi'(Ic), phi''(Ic) of the series.
  Vec3 series(double Ic) const;

  double m_n;
  double m_mu;
  double m_lambda;
  double m_kappa;
};

}  // namespace sinew
