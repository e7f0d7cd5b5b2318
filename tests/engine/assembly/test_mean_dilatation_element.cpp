// The mean-dilatation hex8 element (engine/assembly/mean_dilatation_element.hpp) against
// finite differences, the per-point element, and its projection, for every material of the
// form f(Ic) + g(J).
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/assembly/mean_dilatation_element.hpp"
#include "tests/engine/assembly/element_finite_differences.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

const char* const kMaterials[] = {"stable_neo_hookean", "neo_hookean", "fung", "arruda_boyce"};

struct Fixture {
  Hex8Reference ref = compute_hex8_reference(0.1, IsotropicElasticity::from_young_poisson(1e5, 0.45));
  ElementQuadrature mean{8, ref.dN_dX.data(), ref.det_dXds, true};
  ElementQuadrature per_point{8, ref.dN_dX.data(), ref.det_dXds, false};

  // Rest cell [0, 0.1]^3 mapped by A (affine part) plus a random offset of each node.
  static ElementNodes deformed(const Mat3& A, double amplitude, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    ElementNodes nodes;
    for (int a = 0; a < 8; ++a) {
      nodes.X[a] = (hex8_natural_node(a) + Vec3::Ones()) * 0.05;
      nodes.x[a] = A * nodes.X[a] + Vec3(u(rng), u(rng), u(rng));
    }
    return nodes;
  }
};

std::unique_ptr<InvariantMaterial> invariant(const char* name, double nu) {
  std::unique_ptr<Material> m = make_material(name, {1e5, nu});
  auto* invariant = dynamic_cast<InvariantMaterial*>(m.get());
  REQUIRE(invariant != nullptr);
  m.release();
  return std::unique_ptr<InvariantMaterial>(invariant);
}

Vec24 gradient_of(const InvariantMaterial& m, const ElementQuadrature& quad, const ElementNodes& nodes) {
  Vec24 g;
  mean_dilatation_element_derivatives(m, quad, nodes, false, g, nullptr);
  return g;
}

}  // namespace

// Under an affine map every Gauss point has the same J, so Jbar = J_q and the element is the
// per-point one: energies and gradients agree to round-off.
TEST_CASE("mean dilatation element: equals the per-point element under an affine map") {
  const Fixture f;
  Mat3 A;
  A << 1.1, 0.2, -0.05, 0.03, 0.9, 0.1, -0.1, 0.05, 1.05;
  const ElementNodes nodes = Fixture::deformed(A, 0, 1);
  for (const char* name : kMaterials) {
    CAPTURE(std::string(name));
    const auto m = invariant(name, 0.45);
    Vec24 g_mean, g_point;
    const double e_mean = hyperelastic_element_derivatives(*m, f.mean, nodes, g_mean, nullptr);
    const double e_point = hyperelastic_element_derivatives(*m, f.per_point, nodes, g_point, nullptr);
    CHECK(std::abs(e_mean - e_point) <= 1e-12 * std::abs(e_point));
    CHECK((g_mean - g_point).norm() <= 1e-12 * g_point.norm());
    CHECK(std::abs(hyperelastic_element_energy(*m, f.mean, nodes) - e_mean) <= 1e-12 * std::abs(e_mean));
  }
}

TEST_CASE("mean dilatation element: zero force at rest, gradient = FD of the energy") {
  const Fixture f;
  for (const char* name : kMaterials) {
    CAPTURE(std::string(name));
    const auto m = invariant(name, 0.45);
    CHECK(gradient_of(*m, f.mean, Fixture::deformed(Mat3::Identity(), 0, 1)).norm() < 1e-9);
    // Non-affine: the points' J differ (classic Neo-Hookean needs Jbar > 0, so mild).
    const ElementNodes nodes = Fixture::deformed(Mat3::Identity(), 0.02, 2);
    const Vec24 g = gradient_of(*m, f.mean, nodes);
    double previous = 1e300, last = 0;
    for (double eps : {1e-3, 1e-4, 1e-5}) {
      const Vec24 fd = test::fd_gradient(
          nodes, eps, [&](const ElementNodes& n) { return mean_dilatation_element_energy(*m, f.mean, n); });
      last = (fd - g).norm() / g.norm();
      CHECK(last < previous);  // central differences: O(eps^2) until round-off
      previous = last;
    }
    CHECK(last < 1e-6);
  }
}

TEST_CASE("mean dilatation element: exact Hessian = FD of the gradient, also where indefinite") {
  const Fixture f;
  for (const char* name : kMaterials) {
    CAPTURE(std::string(name));
    const auto m = invariant(name, 0.45);
    const ElementNodes nodes = Fixture::deformed(Mat3::Identity(), 0.02, 3);
    Vec24 g;
    Mat24 K;
    mean_dilatation_element_derivatives(*m, f.mean, nodes, true, g, &K);
    if (std::string(name) == "stable_neo_hookean")  // the case the title claims, checked
      CHECK(test::min_eigenvalue(K) < 0);
    const Mat24 fd = test::fd_jacobian(nodes, 1e-6, [&](const ElementNodes& n) { return gradient_of(*m, f.mean, n); });
    // Truncation O(eps^2 |d3 Psi|) and round-off O(|g| 1e-16 / eps), both far below 1e-6.
    CHECK((fd - K).norm() / K.norm() < 1e-6);
    CHECK((K - K.transpose()).norm() <= 1e-12 * K.norm());
  }
}

// Projection: each point's matrix by its eigensystem, g'' clamped. PSD and finite under
// inverting deformations; equal to the exact Hessian where every part is already PSD. The
// twist and flip values are 2 f' +- g' sigma_k, so that needs |g'| sigma small against f':
// J just past alpha (1.43 at nu 0.3; a stretch of 1.14 gives J 1.48), as in the tet4 test.
TEST_CASE("mean dilatation element: projected Hessian is PSD, and exact where that is PSD") {
  const Fixture f;
  const auto snh = invariant("stable_neo_hookean", 0.49);
  for (unsigned seed = 0; seed < 20; ++seed) {
    const ElementNodes nodes = Fixture::deformed(Mat3::Identity(), 0.08, 100 + seed);  // cell 0.1: inverts
    Vec24 g;
    Mat24 K;
    REQUIRE(std::isfinite(mean_dilatation_element_derivatives(*snh, f.mean, nodes, false, g, &K)));
    REQUIRE(K.allFinite());
    const double smallest = test::min_eigenvalue(0.5 * (K + K.transpose()));
    CHECK(smallest >= -1e-9 * K.norm());
  }
  const auto snh_03 = invariant("stable_neo_hookean", 0.3);
  const ElementNodes expanded = Fixture::deformed(1.14 * Mat3::Identity(), 0.0005, 7);
  Vec24 g;
  Mat24 exact, projected;
  mean_dilatation_element_derivatives(*snh_03, f.mean, expanded, true, g, &exact);
  mean_dilatation_element_derivatives(*snh_03, f.mean, expanded, false, g, &projected);
  REQUIRE(test::min_eigenvalue(exact) > -1e-9 * exact.norm());
  CHECK((exact - projected).norm() <= 1e-10 * exact.norm());
}

TEST_CASE("mean dilatation element: classic Neo-Hookean with Jbar <= 0 is infinite, never NaN") {
  const Fixture f;
  const auto nh = invariant("neo_hookean", 0.45);
  const ElementNodes inverted = Fixture::deformed(Vec3(1, 1, -1).asDiagonal().toDenseMatrix(), 0.01, 4);
  Vec24 g;
  Mat24 K;
  CHECK(std::isinf(mean_dilatation_element_derivatives(*nh, f.mean, inverted, false, g, &K)));
  CHECK(std::isinf(mean_dilatation_element_energy(*nh, f.mean, inverted)));
  CHECK(g.allFinite());
  CHECK(K.allFinite());
}
