#pragma once
// Closed-form uniaxial stretch of the hyperelastic energies of docs/scenes.md, written here
// from their formulas (engine/materials/*.hpp headers, paper 003), independent of the
// engine's material code. An isotropic energy is a function psi(s1, s2, s3) of the principal
// stretches; under F = diag(s, t, t) the nominal (first Piola-Kirchhoff) stress is
// diag(dpsi/ds_i). Uniaxial nominal stress T along axis 1 with free lateral faces means
//   dpsi/ds_2 (s, t, t) = 0      (lateral stress-free: gives t(s))
//   dpsi/ds_1 (s, t(s), t(s)) = T
// solved by nested bisection; derivatives by a fourth-order central difference.
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "engine/core/types.hpp"

namespace sinew::accuracy {

using StretchEnergy = std::function<double(const Vec3&)>;  // psi(s1, s2, s3), J/m^3

// psi of the scene model `model` for Young's modulus E and Poisson's ratio nu, each with
// the Lame mapping its header documents (Hooke's law at small strain). "corotational" (the
// linear corotational element) under a principal stretch without rotation has the energy
// mu |eps|^2 + lambda/2 tr(eps)^2 with eps = diag(s - 1): that of corotational_hyperelastic.
inline StretchEnergy stretch_energy(const std::string& model, double E, double nu) {
  const double mu_l = E / (2 * (1 + nu)), lambda_l = E * nu / ((1 + nu) * (1 - 2 * nu));
  const auto Ic = [](const Vec3& s) { return s.squaredNorm(); };
  const auto J = [](const Vec3& s) { return s.prod(); };
  if (model == "stable_neo_hookean") {  // paper 003 eq. 14, sec. 3.4 mapping
    const double mu = 4.0 / 3.0 * mu_l, lambda = lambda_l + 5.0 / 6.0 * mu_l, alpha = 1 + 3 * mu / (4 * lambda);
    return [=](const Vec3& s) {
      return mu / 2 * (Ic(s) - 3) + lambda / 2 * std::pow(J(s) - alpha, 2) - mu / 2 * std::log(Ic(s) + 1);
    };
  }
  if (model == "neo_hookean")  // paper 003 eq. 5
    return [=](const Vec3& s) {
      return mu_l / 2 * (Ic(s) - 3) - mu_l * std::log(J(s)) + lambda_l / 2 * std::pow(std::log(J(s)), 2);
    };
  if (model == "corotational_hyperelastic" || model == "corotational")  // paper 003 eq. 3
    return [=](const Vec3& s) {
      return mu_l * (s.array() - 1).square().sum() + lambda_l / 2 * std::pow(s.sum() - 3, 2);
    };
  if (model == "arap") return [=](const Vec3& s) { return mu_l * (s.array() - 1).square().sum(); };
  if (model == "stvk")  // mu |E|^2 + lambda/2 tr(E)^2, E = (F^T F - I) / 2
    return [=](const Vec3& s) {
      return mu_l / 4 * (s.array().square() - 1).square().sum() + lambda_l / 8 * std::pow(Ic(s) - 3, 2);
    };
  if (model == "fung") {  // c = 1 (the scene default)
    const double c = 1, kappa = mu_l, lambda = lambda_l + (1 - 2 * c) * mu_l;
    return [=](const Vec3& s) {
      return mu_l / (2 * c) * (std::exp(c * (Ic(s) - 3)) - 1) + lambda / 2 * std::pow(J(s) - 1, 2) - kappa * (J(s) - 1);
    };
  }
  if (model == "arruda_boyce") {  // N = 8 (the scene default), five-term series
    const double n = 8, C[5] = {1.0 / 2, 1.0 / 20, 11.0 / 1050, 19.0 / 7000, 519.0 / 673750};
    double d1 = 0, d2 = 0;  // phi'(3), phi''(3)
    for (int i = 1; i <= 5; ++i) {
      const double a = C[i - 1] / std::pow(n, i - 1);
      d1 += a * i * std::pow(3.0, i - 1);
      d2 += a * i * (i - 1) * std::pow(3.0, i - 2);
    }
    const double mu = mu_l / (2 * d1), kappa = mu_l, lambda = lambda_l + mu_l - 4 * mu * d2;
    return [=](const Vec3& s) {
      double phi = 0;
      for (int i = 1; i <= 5; ++i) phi += C[i - 1] / std::pow(n, i - 1) * (std::pow(Ic(s), i) - std::pow(3.0, i));
      return mu * phi + lambda / 2 * std::pow(J(s) - 1, 2) - kappa * (J(s) - 1);
    };
  }
  throw std::invalid_argument("no closed form for " + model);
}

// dpsi/ds_i, fourth-order central difference: truncation ~ delta^4 psi^(5) ~ 1e-16 E,
// round-off ~ eps psi / delta ~ 1e-12 E at the stretches used.
inline double stretch_derivative(const StretchEnergy& psi, const Vec3& s, int i) {
  const double delta = 1e-4;
  auto at = [&](double k) {
    Vec3 p = s;
    p[i] += k * delta;
    return psi(p);
  };
  return (-at(2) + 8 * at(1) - 8 * at(-1) + at(-2)) / (12 * delta);
}

// A root of f in [lo, hi], where f changes sign, to the resolution of doubles.
inline double bisect(const std::function<double(double)>& f, double lo, double hi) {
  double f_lo = f(lo);
  if ((f_lo > 0) == (f(hi) > 0)) throw std::runtime_error("bisect: no sign change in the bracket");
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi), f_mid = f(mid);
    if ((f_mid > 0) == (f_lo > 0)) {
      lo = mid;
      f_lo = f_mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

struct UniaxialStretch {
  double axial = 1, lateral = 1;
};

// The stretches under nominal stress `traction` (Pa) along axis 1, lateral faces free.
// Brackets: stretches within [0.5, 1.8], which the loads of the tests stay well inside.
inline UniaxialStretch solve_uniaxial(const StretchEnergy& psi, double traction) {
  auto lateral = [&](double s) {
    return bisect([&](double t) { return stretch_derivative(psi, Vec3(s, t, t), 1); }, 0.5, 1.5);
  };
  UniaxialStretch r;
  r.axial = bisect([&](double s) { const double t = lateral(s); return stretch_derivative(psi, Vec3(s, t, t), 0) - traction; },
                   0.6, 1.8);
  r.lateral = lateral(r.axial);
  return r;
}

}  // namespace sinew::accuracy
