#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "engine/constraints/energy_limit.hpp"

using namespace sinew;

namespace {

const double kCell = 0.1;

struct Element {
  Hex8Reference ref = compute_hex8_reference(kCell, IsotropicElasticity::from_young_poisson(1.5e5, 0.3));
  std::array<Vec3, 8> X;
  Element() {
    for (int n = 0; n < 8; ++n) X[n] = (hex8_natural_node(n) + Vec3::Ones()) * kCell / 2;
  }
  // Rotated and deformed by `amount` (a fixed non-rigid pattern).
  std::array<Vec3, 8> deformed(double amount) const {
    const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3(0.3, 1, -0.4).normalized()).toRotationMatrix();
    std::array<Vec3, 8> x;
    for (int n = 0; n < 8; ++n)
      x[n] = Q * X[n] + amount * kCell * Vec3(std::sin(2.0 * n + 1), std::cos(3.0 * n), std::sin(5.0 * n + 2));
    return x;
  }
  // C with R frozen at R0, or recomputed from x when R0 is null.
  double C(const std::array<Vec3, 8>& x, double Umax, const Mat3* R0) const {
    const Mat3 R = R0 ? *R0 : compute_hex8_rotation(x, kCell);
    return 1 - hex8_limit_energy(ref, hex8_corotated_displacement(R, x, X)) / Umax;
  }
  Vec24 fd_gradient(const std::array<Vec3, 8>& x, double Umax, const Mat3* R0, double step) const {
    Vec24 g;
    for (int i = 0; i < 24; ++i) {
      auto xp = x, xm = x;
      xp[i / 3][i % 3] += step;
      xm[i / 3][i % 3] -= step;
      g[i] = (C(xp, Umax, R0) - C(xm, Umax, R0)) / (2 * step);
    }
    return g;
  }
};

}  // namespace

TEST_CASE("energy limit: value is 1 - Ue/Umax and the exact Jacobian is its gradient with R frozen") {
  Element el;
  const auto x = el.deformed(0.05);
  const Mat3 R = compute_hex8_rotation(x, kCell);
  const Vec24 u = hex8_corotated_displacement(R, x, el.X);
  const double Umax = 0.5 * hex8_limit_energy(el.ref, u);  // element at twice its limit
  const EnergyLimitEval eval = evaluate_energy_limit(el.ref.Ke * u, R, u, Umax, EnergyJacobian::Exact);
  CHECK(eval.ratio == doctest::Approx(2.0));
  CHECK(eval.value == doctest::Approx(-1.0));
  for (double step : {1e-3, 1e-4, 1e-5}) {
    const double error = (el.fd_gradient(x, Umax, &R, step) - eval.jac).norm() / eval.jac.norm();
    MESSAGE("FD step " << step << ": relative error " << error);
    // C is quadratic in x with R frozen: central differences are exact up to rounding.
    CHECK(error < 1e-6);
  }
}

TEST_CASE("energy limit: the warped-force Jacobian is f_e / Umax, half the exact gradient") {
  Element el;
  const auto x = el.deformed(0.05);
  const Mat3 R = compute_hex8_rotation(x, kCell);
  const Vec24 u = hex8_corotated_displacement(R, x, el.X);
  const double Umax = 0.1;
  const auto exact = evaluate_energy_limit(el.ref.Ke * u, R, u, Umax, EnergyJacobian::Exact);
  const auto warped = evaluate_energy_limit(el.ref.Ke * u, R, u, Umax, EnergyJacobian::Warped);
  CHECK((warped.jac - hex8_elastic_force(el.ref, R, u) / Umax).norm() < 1e-12 * warped.jac.norm());
  CHECK((2 * warped.jac - exact.jac).norm() < 1e-12 * exact.jac.norm());
  CHECK(warped.value == exact.value);
}

TEST_CASE("energy limit: error of dropping dR/dx, measured against the full gradient") {
  // The paper holds R fixed (sec. 4.2). The full derivative also moves R; the neglected
  // term scales with the strain, so its relative size must fall linearly as the
  // deformation shrinks.
  Element el;
  std::vector<double> errors;
  for (double amount : {0.08, 0.04, 0.02, 0.01}) {
    const auto x = el.deformed(amount);
    const Mat3 R = compute_hex8_rotation(x, kCell);
    const Vec24 u = hex8_corotated_displacement(R, x, el.X);
    const double Umax = 1.0;
    const Vec24 frozen = evaluate_energy_limit(el.ref.Ke * u, R, u, Umax, EnergyJacobian::Exact).jac;
    const Vec24 full = el.fd_gradient(x, Umax, nullptr, 1e-7);
    errors.push_back((full - frozen).norm() / full.norm());
    MESSAGE("deformation " << amount << " cell: |J_full - J_frozen| / |J_full| = " << errors.back());
  }
  for (size_t i = 1; i < errors.size(); ++i) {
    CHECK(errors[i] < errors[i - 1]);
    CHECK(errors[i] > 0.3 * errors[i - 1]);  // first order: halves with the deformation
  }
}
