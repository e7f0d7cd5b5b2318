#pragma once
// Classic Neo-Hookean with log J, paper 003 eq. 5 (Bonet and Wood 2008):
//   Psi = mu/2 (Ic - 3) - mu log J + lambda/2 (log J)^2,   mu = mu_L, lambda = lambda_L
// (rest stable and Hooke at F = I as it stands). f(Ic) = mu/2 (Ic - 3),
// g(J) = -mu log J + lambda/2 (log J)^2, g' = (lambda log J - mu) / J,
// g'' = (mu + lambda - lambda log J) / J^2; Hessian and eigensystem from invariant_material.hpp.
//
// Undefined for J <= 0 (sec. 3.1): "reported, never NaN".
// - is_defined(F) is false iff J <= 0 (or F is not finite);
// - energy(F) = +infinity there (a line search rejects the step);
// - pk1/hessian/projected_hessian never return NaN or infinity: below J = kMinJ (1e-6), including
//   J <= 0, g' and g'' are frozen at their values at kMinJ, i.e. P = mu F + g'(kMinJ) cof(F).
//   g'(kMinJ) < 0, so the force -P pushes along +dJ/dF, toward un-inverting the element; these are
//   no longer derivatives of the energy. Departure from the paper: it leaves J <= 0 undefined.
#include "engine/materials/invariant_material.hpp"

namespace sinew {

class NeoHookean : public InvariantMaterial {
 public:
  static constexpr double kMinJ = 1e-6;

  explicit NeoHookean(const MaterialParameters& params);
  const char* name() const override { return "neo_hookean"; }
  bool is_defined(const Mat3& F) const override;
  InvariantTerms terms(double Ic, double J) const override;

 private:
  double m_mu;
  double m_lambda;
};

}  // namespace sinew
