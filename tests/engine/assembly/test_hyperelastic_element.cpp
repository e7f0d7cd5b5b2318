// Element energy, gradient and projected Hessian of the hyperelastic path against finite
// differences, on a hex8 element (8 Gauss points) with Stable Neo-Hookean.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "engine/assembly/hyperelastic_element.hpp"

using namespace sinew;

namespace {

struct HexFixture {
  Hex8Reference ref = compute_hex8_reference(0.1, IsotropicElasticity::from_young_poisson(1e5, 0.3));
  ElementQuadrature quad{8, ref.dN_dX.data(), ref.det_dXds};
  std::unique_ptr<Material> material = make_material("stable_neo_hookean", {1e5, 0.3});

  ElementNodes deformed(double amplitude, unsigned seed) const {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    ElementNodes nodes;
    for (int a = 0; a < 8; ++a) {
      nodes.X[a] = (hex8_natural_node(a) + Vec3::Ones()) * 0.05;
      nodes.x[a] = nodes.X[a] + Vec3(u(rng), u(rng), u(rng));
    }
    return nodes;
  }
};

}  // namespace

TEST_CASE("hyperelastic element: zero force at rest, gradient = FD of the energy") {
  const HexFixture f;
  ElementNodes rest = f.deformed(0, 1);
  Vec24 g;
  // Stable Neo-Hookean's energy at rest is a constant (lambda/2 (1-alpha)^2 - mu/2 log 4),
  // not zero; its gradient is zero (rest stability, paper 003 sec. 3.4).
  hyperelastic_element_derivatives(*f.material, f.quad, rest, g, nullptr);
  CHECK(g.norm() < 1e-9);

  const ElementNodes nodes = f.deformed(0.02, 2);
  hyperelastic_element_derivatives(*f.material, f.quad, nodes, g, nullptr);
  // Central differences: error O(eps^2); it must fall as eps shrinks and end below 1e-6.
  double previous = 1e300, last = 0;
  for (double eps : {1e-3, 1e-4, 1e-5}) {
    Vec24 fd = Vec24::Zero();
    for (int i = 0; i < 24; ++i) {
      ElementNodes plus = nodes, minus = nodes;
      plus.x[i / 3][i % 3] += eps;
      minus.x[i / 3][i % 3] -= eps;
      fd[i] = (hyperelastic_element_energy(*f.material, f.quad, plus) -
               hyperelastic_element_energy(*f.material, f.quad, minus)) / (2 * eps);
    }
    last = (fd - g).norm() / g.norm();
    CHECK(last < previous);
    previous = last;
  }
  CHECK(last < 1e-6);
}

TEST_CASE("hyperelastic element: Hessian = FD of the gradient where the material Hessian is PSD") {
  const HexFixture f;
  // Small deformation: SNH's Hessian is PSD near rest, so projection changes nothing.
  const ElementNodes nodes = f.deformed(0.002, 3);
  Vec24 g;
  Mat24 K;
  hyperelastic_element_derivatives(*f.material, f.quad, nodes, g, &K);
  const double eps = 1e-6;
  Mat24 fd;
  for (int i = 0; i < 24; ++i) {
    ElementNodes plus = nodes, minus = nodes;
    plus.x[i / 3][i % 3] += eps;
    minus.x[i / 3][i % 3] -= eps;
    Vec24 gp, gm;
    hyperelastic_element_derivatives(*f.material, f.quad, plus, gp, nullptr);
    hyperelastic_element_derivatives(*f.material, f.quad, minus, gm, nullptr);
    fd.col(i) = (gp - gm) / (2 * eps);
  }
  CHECK((fd - K).norm() / K.norm() < 1e-6);
}

TEST_CASE("hyperelastic element: projected Hessian is PSD under large, inverting deformation") {
  const HexFixture f;
  for (unsigned seed = 0; seed < 20; ++seed) {
    const ElementNodes nodes = f.deformed(0.08, 100 + seed);  // cell 0.1: elements invert
    Vec24 g;
    Mat24 K;
    const double energy = hyperelastic_element_derivatives(*f.material, f.quad, nodes, g, &K);
    REQUIRE(std::isfinite(energy));
    REQUIRE(K.allFinite());
    const double smallest = Eigen::SelfAdjointEigenSolver<Mat24>(0.5 * (K + K.transpose())).eigenvalues().minCoeff();
    CHECK(smallest >= -1e-9 * K.norm());
  }
}
