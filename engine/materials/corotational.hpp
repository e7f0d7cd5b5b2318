#pragma once
// Corotational, paper 003 eq. 3 (McAdams et al. 2011):
//   Psi = mu ||F - R||^2 + lambda/2 (tr S - 3)^2,   F = R S polar, mu = mu_L, lambda = lambda_L
// with R = U V^T, S = V diag(sigma) V^T from the rotation-variant SVD, so R stays a rotation
// and tr S = sum sigma (signed) when F is inverted. In singular values:
// psi = mu sum (sigma_i - 1)^2 + lambda/2 (sum sigma - 3)^2, psi_i = 2 mu (sigma_i - 1) + lambda (tr S - 3).
//   P = 2 mu (F - R) + lambda (tr S - 3) R                                   (eq. 4)
//   dP = 2 mu (dF - dR) + lambda (tr S - 3) dR + lambda tr(U^T dF V) R,
//   dR = U Omega V^T, Omega_ij = (M_ij - M_ji) / (sigma_i + sigma_j), M = U^T dF V (i != j)
// Eigensystem (eigen_projection.hpp): scaling = 2 mu I + lambda 1 1^T, flip_k = 2 mu,
//   twist_k = 2 mu + (2 lambda (tr S - 3) - 4 mu) / (sigma_i + sigma_j).
// The rotation-variant SVD keeps sigma_i + sigma_j >= 0; it is 0 where R is not unique
// (F of rank <= 1, or sigma_2 = -sigma_1, e.g. F = diag(1, 1, -1)), where Psi has a kink and
// the true Hessian is unbounded. Departure: the denominator is floored at kMinTwistDenominator
// (1e-6) in both the Hessian and the eigensystem, so they stay finite and consistent there.
#include "engine/materials/isotropic_material.hpp"

namespace sinew {

class Corotational : public IsotropicMaterial {
 public:
  static constexpr double kMinTwistDenominator = 1e-6;

  explicit Corotational(const MaterialParameters& params);
  const char* name() const override { return "corotational"; }
  double energy(const Mat3& F) const override;
  Mat3 pk1(const Mat3& F) const override;
  Mat9 hessian(const Mat3& F) const override;
  SvdEigensystem eigensystem(const Mat3& F) const override;

 protected:
  Corotational(double mu, double lambda) : m_mu(mu), m_lambda(lambda) {}

 private:
  double m_mu;
  double m_lambda;
};

}  // namespace sinew
