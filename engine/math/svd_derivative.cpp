#include "engine/math/svd_derivative.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {

namespace {

// The pair (k, l)'s 2x2 system (header: its solution and clamp): its clamped denominators,
// then a = Omega_U(k, l) and b = Omega_V(k, l) from A_kl and A_lk.
struct PairDenominators {
  double diff, sum;
};
PairDenominators pair_denominators(const Vec3& S, int k, int l, double eps) {
  return {std::min(S(l) - S(k), -eps), std::max(S(l) + S(k), eps)};
}
double pair_omega_V(const PairDenominators& den, double A_kl, double A_lk) {
  return 0.5 * (A_kl + A_lk) / den.diff - 0.5 * (A_kl - A_lk) / den.sum;
}
void solve_pair(const Vec3& S, int k, int l, double A_kl, double A_lk, double eps, double& a, double& b) {
  const PairDenominators den = pair_denominators(S, k, l, eps);
  const double sym = 0.5 * (A_kl + A_lk);
  const double skew = 0.5 * (A_kl - A_lk);
  a = sym / den.diff + skew / den.sum;
  b = pair_omega_V(den, A_kl, A_lk);
}

// Omega_U, Omega_V from A = U^T dF V, pair by pair.
void solve_omegas(const Vec3& S, const Mat3& A, double eps, Mat3& omega_U, Mat3& omega_V) {
  omega_U.setZero();
  omega_V.setZero();
  for (int k = 0; k < 3; ++k)
    for (int l = k + 1; l < 3; ++l) {
      double a, b;
      solve_pair(S, k, l, A(k, l), A(l, k), eps, a, b);
      omega_U(k, l) = a;
      omega_U(l, k) = -a;
      omega_V(k, l) = b;
      omega_V(l, k) = -b;
    }
}

double clamp_epsilon(const RotationVariantSvd& svd, double gap_tolerance) {
  return gap_tolerance * std::max(std::abs(svd.S(0)), 1.0);
}

}  // namespace

SvdDifferential compute_svd_differential(const RotationVariantSvd& svd, const Mat3& dF,
                                         double gap_tolerance) {
  SvdDifferential d;
  const Mat3 A = svd.U.transpose() * dF * svd.V;
  d.dS = A.diagonal();
  solve_omegas(svd.S, A, clamp_epsilon(svd, gap_tolerance), d.omega_U, d.omega_V);
  d.dU = svd.U * d.omega_U;
  d.dV = svd.V * d.omega_V;
  return d;
}

SvdDerivative compute_svd_derivative(const RotationVariantSvd& svd, double gap_tolerance) {
  SvdDerivative d;
  const double eps = clamp_epsilon(svd, gap_tolerance);
  Mat3 omega_U, omega_V;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      // U^T e_r e_c^T V = (row r of U)^T (row c of V).
      const Mat3 A = svd.U.row(r).transpose() * svd.V.row(c);
      d.dS[r][c] = A.diagonal();
      solve_omegas(svd.S, A, eps, omega_U, omega_V);
      d.dU[r][c] = svd.U * omega_U;
      d.dV[r][c] = svd.V * omega_V;
    }
  return d;
}

SvdRotationDerivative compute_svd_rotation_derivative(const RotationVariantSvd& svd, double gap_tolerance) {
  SvdRotationDerivative d;
  const double eps = clamp_epsilon(svd, gap_tolerance);
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  // Each pair's clamped denominators once, not per entry; only b = Omega_V(k, l) is wanted,
  // by solve_pair's own operations (the same bits, half its divisions).
  PairDenominators den[3];
  for (int p = 0; p < 3; ++p) den[p] = pair_denominators(svd.S, kPairs[p][0], kPairs[p][1], eps);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int p = 0; p < 3; ++p) {
        // The pair's b, with A = (row r of U)^T (row c of V).
        const int k = kPairs[p][0], l = kPairs[p][1];
        d.omega_V[r][c](p) = pair_omega_V(den[p], svd.U(r, k) * svd.V(c, l), svd.U(r, l) * svd.V(c, k));
      }
  return d;
}

}  // namespace sinew
