#include "engine/assembly/hyperelastic_element.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "engine/assembly/invariant_tet_hessian.hpp"
#include "engine/assembly/mean_dilatation_element.hpp"
#include "engine/assembly/tet_hessian_scatter.hpp"
#include "engine/materials/invariant_material.hpp"

namespace sinew {

namespace {

// F = sum_a x_a dN_a^T over `count` nodes, position(a) the node's: nine named sums, node
// after node, each entry's terms in node order (Eigen's outer-product update went through the
// stack, and its overlapping 16-byte reloads stalled store forwarding: 73 % of this
// function's samples; an array of sums stayed on the stack).
template <class Position>
Mat3 sum_deformation_gradient(const Mat83& dN_dX, int count, const Position& position) {
  double f00 = 0, f01 = 0, f02 = 0, f10 = 0, f11 = 0, f12 = 0, f20 = 0, f21 = 0, f22 = 0;
  for (int a = 0; a < count; ++a) {
    const double* x = position(a);
    const double d0 = dN_dX(a, 0), d1 = dN_dX(a, 1), d2 = dN_dX(a, 2);
    f00 += x[0] * d0, f10 += x[1] * d0, f20 += x[2] * d0;
    f01 += x[0] * d1, f11 += x[1] * d1, f21 += x[2] * d1;
    f02 += x[0] * d2, f12 += x[1] * d2, f22 += x[2] * d2;
  }
  Mat3 F;
  F << f00, f01, f02, f10, f11, f12, f20, f21, f22;
  return F;
}

}  // namespace

Mat3 deformation_gradient(const Mat83& dN_dX, const ElementNodes& nodes) {
  return sum_deformation_gradient(dN_dX, nodes.count, [&](int a) { return nodes.x[a].data(); });
}

Mat3 tet_deformation_gradient(const Mat83& dN_dX, const VecX& x, const std::array<int, 8>& nodes) {
  return sum_deformation_gradient(dN_dX, 4, [&](int a) { return x.data() + 3 * nodes[a]; });
}

namespace {

// add_point_hessian_to (below) for a tet (n = 4), whose shape function gradients sum to
// zero: node 0's blocks are minus the sums of the others', K_0b = -sum_a K_ab and
// K_00 = -sum_b K_0b, so only the 3 x 3 congruence K_ab = sum_j dN_a,j T_jb, T_jb = w sum_m dN_b,m H_jm, over nodes 1-3 is
// formed: ~880 flops instead of ~1190 (the bunny's assembly: 205 -> ~150 ns a tet).
// hessian: a matrix of 12 rows or more, or a TetHessianScatter.
template <class Sink>
void add_tet_point_hessian_to(const Mat83& dN, const Mat9& H, double w, Sink& hessian) {
  Mat3 T[3][3];  // T[j][b - 1]
  for (int b = 1; b < 4; ++b) {
    const double d0 = w * dN(b, 0), d1 = w * dN(b, 1), d2 = w * dN(b, 2);
    for (int j = 0; j < 3; ++j)
      T[j][b - 1] = d0 * H.block<3, 3>(3 * j, 0) + d1 * H.block<3, 3>(3 * j, 3) + d2 * H.block<3, 3>(3 * j, 6);
  }
  Mat3 K[3][3];  // K[a - 1][b - 1], nodes 1-3
  for (int a = 1; a < 4; ++a)
    for (int b = a; b < 4; ++b) {
      K[a - 1][b - 1] = dN(a, 0) * T[0][b - 1] + dN(a, 1) * T[1][b - 1] + dN(a, 2) * T[2][b - 1];
      if (b != a) K[b - 1][a - 1] = K[a - 1][b - 1].transpose();
    }
  Mat3 K0[3];  // K_0b, b = 1-3
  for (int b = 0; b < 3; ++b) K0[b] = -(K[0][b] + K[1][b] + K[2][b]);
  add_tet_blocks(K, K0, hessian);
}

// hessian(a, b) += w sum_{j,m} dN_a,j dN_b,m H_jm, where H_jm is the 3x3 block of H that
// couples column j of F with column m (vec(F) is column-major). Works on B's non-zero
// pattern instead of the dense 9 x 3n product (B has one non-zero in three). Fills both
// triangles. A tet (n = 4, the 12- and 24-wide paths alike) takes the kernel above.
template <class Matrix>
void add_point_hessian_to(const Mat83& dN, int n, const Mat9& H, double w, Matrix& hessian) {
  if (n == 4) return add_tet_point_hessian_to(dN, H, w, hessian);
  for (int a = 0; a < n; ++a) {
    Mat3 G[3];  // G[m] = w sum_j dN_a,j H_jm
    for (int m = 0; m < 3; ++m)
      G[m] = w * (dN(a, 0) * H.block<3, 3>(0, 3 * m) + dN(a, 1) * H.block<3, 3>(3, 3 * m) +
                  dN(a, 2) * H.block<3, 3>(6, 3 * m));
    for (int b = a; b < n; ++b) {
      const Mat3 K = dN(b, 0) * G[0] + dN(b, 1) * G[1] + dN(b, 2) * G[2];
      hessian.template block<3, 3>(3 * a, 3 * b) += K;
      if (b != a) hessian.template block<3, 3>(3 * b, 3 * a) += K.transpose();
    }
  }
}

}  // namespace

void add_point_hessian(const Mat83& dN, int n, const Mat9& H, double w, Mat24& hessian) {
  add_point_hessian_to(dN, n, H, w, hessian);
}

void add_point_hessian(const Mat83& dN, int n, const Mat9& H, double w, Mat12& hessian) {
  add_point_hessian_to(dN, n, H, w, hessian);
}

double hyperelastic_element_energy(const Material& material, const ElementQuadrature& quad,
                                   const ElementNodes& nodes) {
  if (quad.mean_dilatation)  // build_model admits it only for invariant materials
    return mean_dilatation_element_energy(static_cast<const InvariantMaterial&>(material), quad, nodes);
  double energy = 0;
  for (int q = 0; q < quad.points; ++q) {
    const Mat3 F = deformation_gradient(quad.dN_dX[q], nodes);
    if (!material.is_defined(F)) return std::numeric_limits<double>::infinity();
    energy += quad.weight * material.energy(F);
  }
  return energy;
}

namespace {

// Whether a Hessian goes straight into the system's values (tet_hessian_scatter.hpp).
template <class Matrix>
constexpr bool kScatters = std::is_same_v<std::remove_const_t<Matrix>, TetHessianScatter>;

// One point's energy (+infinity where undefined), PK1 and (if hessian) Hessian, projected
// unless `exact` and defined, added times w; an invariant material's terms taken once.
// A TetHessianScatter takes a tet's (n = 4) only.
template <class Matrix>
double add_point(const Material& material, const Mat3& F, const Mat83& dN, int n, double w, Mat3& P,
                 Matrix* hessian, bool exact, const RotationVariantSvd* svd) {
  const bool defined = material.is_defined(F);
  const InvariantMaterial* invariant = material.as_invariant();
  if (!invariant) {
    P = material.pk1(F);
    if (hessian) {
      const Mat9 H = exact && defined ? material.hessian(F) : material.projected_hessian(F);
      if constexpr (kScatters<Matrix>) add_tet_point_hessian_to(dN, H, w, *hessian);
      else add_point_hessian(dN, n, H, w, *hessian);
    }
    return defined ? w * material.energy(F) : std::numeric_limits<double>::infinity();
  }
  const InvariantTerms t = invariant->terms(F.squaredNorm(), F.determinant());
  P = invariant_pk1(F, t);
  const bool project = !(exact && defined);
  if (hessian && n == 4) {
    if constexpr (std::is_same_v<Matrix, Mat12> || kScatters<Matrix>) {
      add_invariant_tet_hessian(F, t, project, dN, w, *hessian, svd);
    } else {  // the padded path: the same entries, bit for bit (a tet has one point)
      Mat12 K = Mat12::Zero();
      add_invariant_tet_hessian(F, t, project, dN, w, K);
      hessian->template topLeftCorner<12, 12>() += K;
    }
  } else if (hessian) {
    if constexpr (!kScatters<Matrix>)
      add_point_hessian(dN, n, project ? invariant_projected_hessian(F, t) : invariant_hessian(F, t), w, *hessian);
  }
  return defined ? w * t.psi : std::numeric_limits<double>::infinity();
}

// sum_q of the points' energies, gradients and projected Hessians (exact ones, with `exact`,
// at points where the material is defined) over the first n nodes, into a gradient and
// Hessian of 3 n or more entries (Vec24/Mat24 padded, Vec12/Mat12 for a tet).
// given: F and its SVD at the one point of a tet, when the caller has them.
template <class Vector, class Matrix>
double sum_over_points(const Material& material, const ElementQuadrature& quad, const ElementNodes& nodes,
                       Vector& gradient, Matrix* hessian, bool exact = false,
                       const GivenDeformation* given = nullptr) {
  if (quad.points != 1) given = nullptr;
  double energy = 0;
  if constexpr (!kScatters<Matrix>)
    if (hessian) hessian->setZero();
  const int n = nodes.count;
  // The first point's terms are written as 0 + term (the bits of adding them to zeros,
  // without zeroing the vector first: GCC zeroed a Vec12 by `rep stos`, 18 % of the gradient
  // pass's time in this function); the padding past 3 n is zeroed.
  for (int i = 3 * n; i < gradient.size(); ++i) gradient[i] = 0;
  for (int q = 0; q < quad.points; ++q) {
    const Mat83& dN = quad.dN_dX[q];
    Mat3 P;
    energy += add_point(material, given ? given->F : deformation_gradient(dN, nodes), dN, n, quad.weight, P,
                        hessian, exact, given ? given->svd : nullptr);
    for (int a = 0; a < n; ++a) {
      const Vec3 term = quad.weight * (P * dN.row(a).transpose());
      if (q == 0) gradient.template segment<3>(3 * a) = Vec3::Zero() + term;
      else gradient.template segment<3>(3 * a) += term;
    }
  }
  return energy;
}

// With the exact Hessian; where the energy is undefined at some point (inverted
// neo_hookean), the projected one at every point, as there the exact one is not its Hessian.
template <class Vector, class Matrix>
double exact_sum_over_points(const Material& material, const ElementQuadrature& quad, const ElementNodes& nodes,
                             Vector& gradient, Matrix& hessian) {
  const double energy = sum_over_points(material, quad, nodes, gradient, &hessian, true);
  return std::isfinite(energy) ? energy : sum_over_points(material, quad, nodes, gradient, &hessian);
}

}  // namespace

double hyperelastic_element_derivatives(const Material& material, const ElementQuadrature& quad,
                                        const ElementNodes& nodes, Vec24& gradient, Mat24* hessian) {
  if (quad.mean_dilatation)
    return mean_dilatation_element_derivatives(static_cast<const InvariantMaterial&>(material), quad, nodes,
                                               false, gradient, hessian);
  return sum_over_points(material, quad, nodes, gradient, hessian);
}

double hyperelastic_tet_derivatives(const Material& material, const ElementQuadrature& quad,
                                    const ElementNodes& nodes, Vec12& gradient, Mat12* hessian,
                                    const GivenDeformation* given) {
  return sum_over_points(material, quad, nodes, gradient, hessian, false, given);
}

double hyperelastic_tet_derivatives(const Material& material, const ElementQuadrature& quad,
                                    const ElementNodes& nodes, Vec12& gradient, const TetHessianScatter& hessian,
                                    const GivenDeformation* given) {
  if (nodes.count != 4 || quad.points != 1 || quad.mean_dilatation)
    throw std::logic_error("hyperelastic_tet_derivatives: a TetHessianScatter takes a one-point tet only");
  return sum_over_points(material, quad, nodes, gradient, &hessian, false, given);
}

double invariant_tet_energy_gradient(const InvariantMaterial& material, const Mat3& F, const Mat83& dN, double w,
                                     Vec12& gradient) {
  const InvariantTerms t = material.terms(F.squaredNorm(), F.determinant());
  const Mat3 P = invariant_pk1(F, t);
  for (int a = 0; a < 4; ++a) gradient.segment<3>(3 * a) = Vec3::Zero() + w * (P * dN.row(a).transpose());
  // 0 + energy, as sum_over_points sums it (the sign of a zero energy)
  return 0.0 + (material.is_defined(F) ? w * t.psi : std::numeric_limits<double>::infinity());
}

double hyperelastic_element_exact_derivatives(const Material& material, const ElementQuadrature& quad,
                                              const ElementNodes& nodes, Vec24& gradient, Mat24& hessian) {
  if (quad.mean_dilatation) {
    const auto& invariant = static_cast<const InvariantMaterial&>(material);
    const double energy = mean_dilatation_element_derivatives(invariant, quad, nodes, true, gradient, &hessian);
    // Undefined energy (neo_hookean, Jbar <= 0): the projected Hessian, as above.
    return std::isfinite(energy) ? energy
                                 : mean_dilatation_element_derivatives(invariant, quad, nodes, false, gradient, &hessian);
  }
  return exact_sum_over_points(material, quad, nodes, gradient, hessian);
}

double hyperelastic_tet_exact_derivatives(const Material& material, const ElementQuadrature& quad,
                                          const ElementNodes& nodes, Vec12& gradient, Mat12& hessian) {
  return exact_sum_over_points(material, quad, nodes, gradient, hessian);
}

}  // namespace sinew
