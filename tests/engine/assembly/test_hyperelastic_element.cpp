// Element energy, gradient and projected Hessian of the hyperelastic path against finite
// differences, on a hex8 element (8 Gauss points) with Stable Neo-Hookean.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>

#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/core/cpu_features.hpp"
#include "engine/fem/tet4.hpp"
#include "engine/materials/invariant_material.hpp"
#include "tests/engine/assembly/element_finite_differences.hpp"
#include "tests/support/dense_decompositions.hpp"

using namespace sinew;

namespace {

struct HexFixture {
  Hex8Reference ref = compute_hex8_reference(0.1, IsotropicElasticity::from_young_poisson(1e5, 0.3));
  ElementQuadrature quad{8, ref.dN_dX.data(), ref.det_dXds};
  std::unique_ptr<Material> material = make_material("stable_neo_hookean", {1e5, 0.3});

  // x = scale X + a uniform perturbation of +-amplitude per coordinate, drawn x, y, z in turn
  // (not as the arguments of one call, whose order of evaluation differs between compilers).
  ElementNodes deformed(double amplitude, unsigned seed, double scale = 1) const {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    ElementNodes nodes;
    for (int a = 0; a < 8; ++a) {
      nodes.X[a] = (hex8_natural_node(a) + Vec3::Ones()) * 0.05;
      nodes.x[a] = scale * nodes.X[a];
      for (int i = 0; i < 3; ++i) nodes.x[a][i] += u(rng);
    }
    return nodes;
  }
};

// One tet (the unit corner tet scaled to 0.1 m) and its one-point quadrature.
struct TetFixture {
  std::array<Vec3, 4> X{Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(0, 0, 0.1)};
  Tet4Reference ref = compute_tet4_reference(X, IsotropicElasticity::from_young_poisson(1e5, 0.3));
  Mat83 dN = padded(ref.dN_dX);
  ElementQuadrature quad{1, &dN, ref.volume};

  static Mat83 padded(const Eigen::Matrix<double, 4, 3>& dN_dX) {
    Mat83 out = Mat83::Zero();
    out.topRows<4>() = dN_dX;
    return out;
  }
  // x_a = place(X_a), nodes 4-7 zero.
  template <class Place>
  ElementNodes nodes(const Place& place) const {
    ElementNodes n;
    n.count = 4;
    for (auto& p : n.x) p.setZero();
    for (auto& p : n.X) p.setZero();
    for (int a = 0; a < 4; ++a) {
      n.X[a] = X[a];
      n.x[a] = place(X[a]);
    }
    return n;
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
    const Vec24 fd = test::fd_gradient(
        nodes, eps, [&](const ElementNodes& n) { return hyperelastic_element_energy(*f.material, f.quad, n); });
    last = (fd - g).norm() / g.norm();
    CHECK(last < previous);
    previous = last;
  }
  CHECK(last < 1e-6);
}

TEST_CASE("hyperelastic element: Hessian = FD of the gradient where the material Hessian is PSD") {
  const HexFixture f;
  // SNH's Hessian is only semi-definite at rest (zero along rotations) and turns indefinite
  // under any compression; stretched 3 % and perturbed by 2 % it is PSD at every Gauss point
  // (checked: the precondition of comparing with the projected Hessian).
  const ElementNodes nodes = f.deformed(0.002, 3, 1.03);
  for (int q = 0; q < f.quad.points; ++q)
    REQUIRE(test::min_eigenvalue(f.material->hessian(deformation_gradient(f.quad.dN_dX[q], nodes))) > 0);
  Vec24 g;
  Mat24 K;
  hyperelastic_element_derivatives(*f.material, f.quad, nodes, g, &K);
  const Mat24 fd = test::fd_jacobian(nodes, 1e-6, [&](const ElementNodes& n) {
    Vec24 gn;
    hyperelastic_element_derivatives(*f.material, f.quad, n, gn, nullptr);
    return gn;
  });
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
    const double smallest = test::min_eigenvalue(0.5 * (K + K.transpose()));
    CHECK(smallest >= -1e-9 * K.norm());
  }
}

// A tet fills 4 of the 8 padded node slots: its Hessian (12 x 12 block) matches finite
// differences of the gradient, and the padding stays zero. At rest SNH's twist eigenvalues
// are exactly 0 and a small shear makes one negative (projected away), so the tet is
// expanded past J = alpha (1.43 at nu 0.3), where every eigenvalue is positive: checked.
TEST_CASE("hyperelastic element: tet4 Hessian = FD of the gradient, padding zero") {
  const TetFixture t;
  const Mat83& dN = t.dN;
  const ElementQuadrature& quad = t.quad;
  const auto material = make_material("stable_neo_hookean", {1e5, 0.3});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.002, 0.002);
  const ElementNodes nodes = t.nodes([&](const Vec3& X) {
    const double dx = u(rng), dy = u(rng), dz = u(rng);  // drawn x, y, z in turn
    return Vec3(1.14 * X + Vec3(dx, dy, dz));
  });
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < 4; ++a) F += nodes.x[a] * dN.row(a);
  REQUIRE(test::min_eigenvalue(material->hessian(F)) > 0);
  Vec24 g;
  Mat24 K;
  hyperelastic_element_derivatives(*material, quad, nodes, g, &K);
  CHECK(K.rightCols<12>().norm() == 0);
  CHECK(K.bottomRows<12>().norm() == 0);
  const Mat12 fd = test::fd_jacobian(nodes, 1e-7, [&](const ElementNodes& n) {
                     Vec24 gn;
                     hyperelastic_element_derivatives(*material, quad, n, gn, nullptr);
                     return gn;
                   }).topLeftCorner<12, 12>();
  const Mat12 K12 = K.topLeftCorner<12, 12>();
  // Central differences: truncation O(eps^2 |d3 Psi|), round-off O(|g| 1e-16 / eps).
  CHECK((fd - K12).norm() / K12.norm() < 1e-6);
  CHECK((K12 - K12.transpose()).norm() <= 1e-12 * K12.norm());
}

TEST_CASE("hyperelastic element: the 12 x 12 tet path equals the padded one bit for bit, also from a given SVD and scattered") {
  // Same sums in the same order (hyperelastic_element.hpp), on tets stretched, compressed,
  // sheared and inverted (J < 0, where the projection removes modes), for two materials.
  const TetFixture t;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  // Two invariant materials (invariant_tet_hessian.cpp) and two others (the 9 x 9 Hessian's
  // congruence, hyperelastic_element.cpp).
  if (!use_avx2()) MESSAGE("this CPU has no AVX2: the scatter runs the scalar kernel twice");
  for (const char* name : {"stable_neo_hookean", "neo_hookean", "corotational", "stvk"}) {
    const auto material = make_material(name, {1e5, 0.45});
    int inverted = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const ElementNodes nodes = t.nodes([&](const Vec3& X) {
        const double dx = u(rng), dy = u(rng), dz = u(rng);
        return Vec3(X + Vec3(dx, dy, dz));
      });
      const ElementQuadrature& quad = t.quad;
      const Mat83& dN = t.dN;
      inverted += deformation_gradient(dN, nodes).determinant() < 0;
      Vec24 g24;
      Mat24 K24;
      Vec12 g12;
      Mat12 K12;
      const double e24 = hyperelastic_element_derivatives(*material, quad, nodes, g24, &K24);
      const double e12 = hyperelastic_tet_derivatives(*material, quad, nodes, g12, &K12);
      CHECK(((e12 == e24) || (std::isinf(e12) && std::isinf(e24))));
      CHECK(g12 == g24.head<12>());
      CHECK(K12 == K24.topLeftCorner<12, 12>());
      Vec12 g_only;
      CHECK(((hyperelastic_tet_derivatives(*material, quad, nodes, g_only, nullptr) == e12) || std::isinf(e12)));
      CHECK(g_only == g12);
      // With F and its SVD given (solve_newton's batches): the same bits.
      const Mat3 F = deformation_gradient(dN, nodes);
      const RotationVariantSvd svd = compute_rotation_variant_svd(F);
      const GivenDeformation given{F, &svd};
      Vec12 g_svd;
      Mat12 K_svd;
      const double e_svd = hyperelastic_tet_derivatives(*material, quad, nodes, g_svd, &K_svd, &given);
      CHECK(((e_svd == e12) || (std::isinf(e_svd) && std::isinf(e12))));
      CHECK(g_svd == g12);
      CHECK(K_svd == K12);
      // Straight into a system's values (the assembly's path): a dense 12 x 12 column-major
      // "system" with node 2 fixed (its blocks have no positions), holding earlier sums.
      // Each value gets base + coeff * K12 entry, as scatter_element_matrix would add it;
      // invariant materials' blocks by the AVX2 kernel (invariant_tet_blocks.hpp) where the
      // CPU has it, and by the scalar one.
      for (const bool baseline : {false, true}) {
        CAPTURE(baseline);
        std::optional<BaselineKernelsOnly> scalar_only;
        if (baseline) scalar_only.emplace();
        int positions[48];
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b)
            for (int d = 0; d < 3; ++d)
              positions[3 * (4 * a + b) + d] = a == 2 || b == 2 ? -1 : (3 * b + d) * 12 + 3 * a;
        Mat12 values = Mat12::Constant(0.25);
        values(4, 3) = 0;  // a +0 entry that receives a product, as off the diagonal of a fresh system
        const Mat12 base = values;
        const double coeff = 1.0 / 3600;
        Vec12 g_scatter;
        const double e_scatter = hyperelastic_tet_derivatives(*material, quad, nodes, g_scatter,
                                                              TetHessianScatter{positions, coeff, values.data()}, &given);
        CHECK(((e_scatter == e12) || (std::isinf(e_scatter) && std::isinf(e12))));
        CHECK(g_scatter == g12);
        for (int r = 0; r < 12; ++r)
          for (int c = 0; c < 12; ++c) {
            const bool fixed = r / 3 == 2 || c / 3 == 2;
            const double expected = fixed ? base(r, c) : base(r, c) + coeff * K12(r, c);
            CHECK(std::bit_cast<uint64_t>(values(r, c)) == std::bit_cast<uint64_t>(expected));  // zero signs too
          }
      }
    }
    REQUIRE(inverted > 0);  // the inverted branch was exercised
  }
}

TEST_CASE("hyperelastic tet, exact Hessian: w B^T d2Psi/dF2 B, or the projected one where the material is undefined") {
  const TetFixture t;
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  for (const char* name : {"stable_neo_hookean", "neo_hookean"}) {
    const auto material = make_material(name, {1e5, 0.45});
    int inverted = 0, indefinite = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const ElementNodes nodes = t.nodes([&](const Vec3& X) { return Vec3(X + Vec3(u(rng), u(rng), u(rng))); });
      const Mat3 F = deformation_gradient(t.dN, nodes);
      Vec12 g, g_projected;
      Mat12 K, K_projected;
      const double energy = hyperelastic_tet_exact_derivatives(*material, t.quad, nodes, g, K);
      const double energy_projected = hyperelastic_tet_derivatives(*material, t.quad, nodes, g_projected, &K_projected);
      CHECK(((energy == energy_projected) || (std::isinf(energy) && std::isinf(energy_projected))));
      CHECK(g == g_projected);
      if (!material->is_defined(F)) {
        ++inverted;
        CHECK(K == K_projected);
        continue;
      }
      // B(i + 3j, 3a + i) = dN_a,j: vec(F) = B x (column-major vec, material.hpp).
      Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
      for (int a = 0; a < 4; ++a)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) B(i + 3 * j, 3 * a + i) = t.dN(a, j);
      const Mat12 expected = t.quad.weight * (B.transpose() * material->hessian(F) * B);
      CHECK((K - expected).norm() <= 1e-12 * expected.norm());
      indefinite += Eigen::SelfAdjointEigenSolver<Mat12>(K).eigenvalues().minCoeff() < -1e-9 * expected.norm();
    }
    MESSAGE(std::string(name) << ": " << inverted << " undefined, " << indefinite << " indefinite exact Hessians of 200");
    if (std::string(name) == "neo_hookean") REQUIRE(inverted > 0);  // the fallback was exercised
    REQUIRE(indefinite > 0);  // the exact Hessian is not the projected one
  }
}

TEST_CASE("hyperelastic tet, projected Hessian of an invariant material: term by term equals w B^T P(d2Psi/dF2) B") {
  // The tet path builds the invariant materials' Hessian in 12 x 12 term by term
  // (invariant_tet_hessian.hpp) instead of w B^T H B from the 9 x 9 H; the two sum the same
  // terms in another order, so they agree to round-off: a few hundred eps of the largest
  // term, which is of the size of the result's norm (1e-12 leaves a factor of ~20 over that).
  const TetFixture t;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) B(i + 3 * j, 3 * a + i) = t.dN(a, j);
  for (const char* name : {"stable_neo_hookean", "neo_hookean", "fung", "arruda_boyce"}) {
    const auto material = make_material(name, {1e5, 0.45});
    REQUIRE(material->as_invariant() != nullptr);
    int pair_modes = 0, scaling_modes = 0;
    for (int trial = 0; trial < 300; ++trial) {
      // A third of the trials squeezed along a random axis to half its length or less, where
      // the scaling block loses definiteness; the rest scattered at random.
      const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
      const double squeeze = trial % 3 == 0 ? 0.5 + 4 * u(rng) : 0.0;
      const ElementNodes nodes = t.nodes([&](const Vec3& X) {
        return Vec3(X - squeeze * axis * axis.dot(X) + Vec3(u(rng), u(rng), u(rng)));
      });
      const Mat3 F = deformation_gradient(t.dN, nodes);
      const SvdEigensystem eigensystem = material->as_invariant()->eigensystem(F);
      pair_modes += (eigensystem.twist.array() < 0).any() || (eigensystem.flip.array() < 0).any();
      scaling_modes += Eigen::SelfAdjointEigenSolver<Mat3>(eigensystem.scaling).eigenvalues().minCoeff() < 0;
      Vec12 g;
      Mat12 K;
      hyperelastic_tet_derivatives(*material, t.quad, nodes, g, &K);
      const Mat12 expected = t.quad.weight * (B.transpose() * material->projected_hessian(F) * B);
      CHECK((K - expected).norm() <= 1e-12 * expected.norm());
      CHECK((K - K.transpose()).norm() <= 1e-12 * expected.norm());  // node 0's block: sums in two orders
    }
    MESSAGE(std::string(name) << ": negative twist or flip modes removed in " << pair_modes << ", scaling modes in "
                              << scaling_modes << " of 300");
    REQUIRE(pair_modes > 0);
    REQUIRE(scaling_modes > 0);
  }
}

TEST_CASE("hyperelastic tet, energies and gradient alone: the bits of the full path, F read from the positions") {
  // invariant_tet_energy_gradient is the gradient passes' path (hyperelastic_derivatives.cpp)
  // and must give what hyperelastic_tet_derivatives gives the Hessian passes: Newton's line
  // search compares energies from both, and kept tets mix them in one gradient. At rest, stretched, sheared and inverted (neo_hookean's energy
  // undefined there: +infinity), for every invariant material.
  const TetFixture t;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  const auto same_bits = [](double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); };
  for (const char* name : {"stable_neo_hookean", "neo_hookean", "fung", "arruda_boyce"}) {
    CAPTURE(name);
    const auto material = make_material(name, {1e5, 0.45});
    REQUIRE(material->as_invariant() != nullptr);
    int inverted = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const bool at_rest = trial == 0;
      const ElementNodes nodes = t.nodes([&](const Vec3& X) {
        const double dx = u(rng), dy = u(rng), dz = u(rng);
        return at_rest ? X : Vec3(X + Vec3(dx, dy, dz));
      });
      // The positions as a model holds them: four nodes at scattered indices of one vector.
      VecX x = VecX::Constant(30, std::nan(""));
      const std::array<int, 8> indices{7, 2, 9, 4, -1, -1, -1, -1};
      for (int a = 0; a < 4; ++a) x.segment<3>(3 * indices[a]) = nodes.x[a];
      const Mat3 F = tet_deformation_gradient(t.dN, x, indices);
      CHECK(F == deformation_gradient(t.dN, nodes));
      inverted += F.determinant() < 0;
      Vec12 g_full, g_lean;
      const double e_full = hyperelastic_tet_derivatives(*material, t.quad, nodes, g_full, nullptr);
      const double e_lean = invariant_tet_energy_gradient(*material->as_invariant(), F, t.dN, t.quad.weight, g_lean);
      CHECK(same_bits(e_lean, e_full));
      for (int i = 0; i < 12; ++i) CHECK(same_bits(g_lean[i], g_full[i]));
    }
    REQUIRE(inverted > 0);
  }
}
