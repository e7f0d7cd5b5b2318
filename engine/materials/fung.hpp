#pragma once
// Fung (exponential) elasticity, the extension of paper 003 sec. 7. The extracted text stops
// before sec. 7, so this is the standard isotropic Fung form in the first invariant, plus the
// paper's rest-stable volume term (eqs. 11-13):
//   Psi = mu/(2 c) (exp(c (Ic - 3)) - 1) + lambda/2 (J - 1)^2 - kappa (J - 1)
// c = MaterialParameters::fung_c > 0 (c -> 0 gives mu/2 (Ic - 3)). The volume term equals
// lambda/2 (J - alpha)^2, alpha = 1 + kappa/lambda, up to a constant; written this way
// Psi(I) = 0 and lambda <= 0 stays allowed.
// Constants (P(I) = 0 and Hooke at F = I, from P_lin = 4 f'(3) eps + (4 f''(3) + lambda - 2 f'(3)) tr(eps) I):
//   mu = mu_L, kappa = 2 f'(3) = mu_L, lambda = lambda_L + mu_L - 4 f''(3) = lambda_L + (1 - 2 c) mu_L.
// lambda < 0 when c > (lambda_L + mu_L) / (2 mu_L): the exponential then supplies the bulk
// stiffness; the Hessian is still Hooke's (PD) at rest and projected elsewhere.
// Hessian and eigensystem: invariant_material.hpp (f(Ic) = the exponential term).
// Departure: for x = c (Ic - 3) > kMaxExponent (100) exp(x) is continued by its second-order
// Taylor polynomial at kMaxExponent (C^2), so energy, P and H stay finite for any stretch.
#include "engine/materials/invariant_material.hpp"

namespace sinew {

class Fung : public InvariantMaterial {
 public:
  static constexpr double kMaxExponent = 100;

  // Throws std::invalid_argument unless fung_c > 0.
  explicit Fung(const MaterialParameters& params);
  const char* name() const override { return "fung"; }
  InvariantTerms terms(double Ic, double J) const override;

  double lambda() const { return m_lambda; }

 private:
  double m_c;
  double m_mu;
  double m_lambda;
  double m_kappa;
};

}  // namespace sinew
