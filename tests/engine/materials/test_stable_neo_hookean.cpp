#include <doctest/doctest.h>

#include "engine/materials/invariant_material.hpp"
#include "engine/materials/stable_neo_hookean.hpp"
#include "tests/engine/materials/material_checks.hpp"

using namespace sinew;
using namespace sinew::material_checks;

TEST_CASE("stable Neo-Hookean: Lame reparameterisation and rest-stable alpha (paper 003, sec. 3.4)") {
  const MaterialParameters p = parameters(0.45);
  const LameParameters lame = lame_parameters(p);
  const StableNeoHookean m(p);
  CHECK(m.mu() == doctest::Approx(4.0 / 3.0 * lame.mu).epsilon(1e-14));
  CHECK(m.lambda() == doctest::Approx(lame.lambda + 5.0 / 6.0 * lame.mu).epsilon(1e-14));
  CHECK(m.alpha() == doctest::Approx(1 + 3 * m.mu() / (4 * m.lambda())).epsilon(1e-14));
}

TEST_CASE("stable Neo-Hookean: P(I) = 0, no force under rotation, Hooke's law at small strain") {
  for (double nu : {0.0, 0.3, 0.45, 0.49}) {
    INFO("nu = ", nu);
    const MaterialParameters p = parameters(nu);
    const StableNeoHookean m(p);
    check_rest(m, p);
    check_hooke(m, p);
  }
}

TEST_CASE("stable Neo-Hookean: P and Hessian against finite differences, shrinking step") {
  for (double nu : {0.3, 0.45}) check_derivatives(StableNeoHookean(parameters(nu)), samples());
}

TEST_CASE("stable Neo-Hookean: closed-form eigensystem and projection") {
  const StableNeoHookean m(parameters(0.45));
  for (const Sample& s : samples()) {
    INFO(s.name);
    check_eigensystem(m, s.F);
    check_projection(m, s.F);
  }
  check_projection_keeps_psd(m, near_rest());
}

TEST_CASE("stable Neo-Hookean: closed-form eigenvalues are the paper's (sec. 4.5)") {
  // twist_k = mu (1 - 1/(Ic + 1)) + lambda (J - alpha) sigma_k, flip_k = ... - lambda (J - alpha) sigma_k.
  const StableNeoHookean m(parameters(0.45));
  const Mat3 F = with_singular_values(Vec3(1.3, 0.9, -0.6));
  const SvdEigensystem system = m.eigensystem(F);
  const double Ic = F.squaredNorm(), J = F.determinant();
  const double shear = m.mu() * (1 - 1 / (Ic + 1));
  for (int k = 0; k < 3; ++k) {
    const double volume = m.lambda() * (J - m.alpha()) * system.svd.S(k);
    CHECK(system.twist(k) == doctest::Approx(shear + volume).epsilon(1e-12));
    CHECK(system.flip(k) == doctest::Approx(shear - volume).epsilon(1e-12));
  }
}

TEST_CASE("stable Neo-Hookean: finite on inverted and degenerate F; point degeneracy (sec. 3.3)") {
  const StableNeoHookean m(parameters(0.49));
  check_finite(m);
  // At F = 0 the forces vanish and, with delta = 1 in log(Ic + delta), the Hessian is exactly
  // zero: semi-definite (2 f'(0) = mu (1 - 1/1) = 0, and every J term carries a factor of F).
  CHECK(m.pk1(Mat3::Zero()).norm() == 0);
  CHECK(m.hessian(Mat3::Zero()).norm() == 0);
  // Inverted: the energy is larger than at rest and the force points toward larger J.
  const Mat3 F = Vec3(1, 1, -1).asDiagonal();
  CHECK(m.energy(F) > m.energy(Mat3::Identity()));
  CHECK((-m.pk1(F)).cwiseProduct(cofactor_matrix(F)).sum() > 0);
}
