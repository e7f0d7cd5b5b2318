#pragma once
// St. Venant-Kirchhoff (the classic energy paper 003 compares against):
//   Psi = mu ||E||^2 + lambda/2 tr(E)^2,   E = (F^T F - I)/2,   mu = mu_L, lambda = lambda_L
//   P = F (2 mu E + lambda tr(E) I)
//   dP = dF (2 mu E + lambda tr(E) I) + F (2 mu dE + lambda tr(dE) I),  dE = (dF^T F + F^T dF)/2
// In singular values psi = mu/4 sum (sigma_i^2 - 1)^2 + lambda/8 (Ic - 3)^2, which gives the
// eigensystem (eigen_projection.hpp) without division:
//   twist_k = mu (sigma_i^2 - sigma_i sigma_j + sigma_j^2 - 1) + lambda/2 (Ic - 3)
//   flip_k  = mu (sigma_i^2 + sigma_i sigma_j + sigma_j^2 - 1) + lambda/2 (Ic - 3)
//   scaling_ii = mu (3 sigma_i^2 - 1) + lambda/2 (Ic - 3) + lambda sigma_i^2,
//   scaling_ij = lambda sigma_i sigma_j.
// Finite for every F; it does not resist inversion (Psi(-I) = Psi(I) = 0) or collapse
// (Psi(0) is finite), which is the known weakness, not a departure.
#include "engine/materials/isotropic_material.hpp"

namespace sinew {

class Stvk : public IsotropicMaterial {
 public:
  explicit Stvk(const MaterialParameters& params);
  const char* name() const override { return "stvk"; }
  double energy(const Mat3& F) const override;
  Mat3 pk1(const Mat3& F) const override;
  Mat9 hessian(const Mat3& F) const override;
  SvdEigensystem eigensystem(const Mat3& F) const override;

 private:
  double m_mu;
  double m_lambda;
};

}  // namespace sinew
