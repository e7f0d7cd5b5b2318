#pragma once
// Energy, gradient and projected Hessian of one element of a hyperelastic body (paper 003),
// for hex8 (8 Gauss points) and tet4 (one point) alike:
//   Psi_e(x) = sum_q w_q Psi(F_q),   F_q = sum_a x_a (dN_a/dX)(q)^T
//   dPsi_e/dx_a = sum_q w_q P(F_q) dN_a(q)
//   d2Psi_e/dx_a,k dx_b,l = sum_q w_q sum_{j,m} H_(k+3j),(l+3m) dN_a,j dN_b,m
// with vec(F) column-major (engine/materials/material.hpp), so dvec(F)/dx = B with
// B(i + 3j, 3a + i) = dN_a,j. Results are padded to 8 nodes like element_kernels.hpp.
// A quadrature with mean_dilatation set goes to mean_dilatation_element.hpp instead.
#include <array>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/tet_hessian_scatter.hpp"
#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

class InvariantMaterial;

// F at one point: sum_a x_a (dN_a/dX)^T.
Mat3 deformation_gradient(const Mat83& dN_dX, const ElementNodes& nodes);
// The same for a tet, its four nodes' positions read from x (the whole position vector) at
// the indices `nodes`: the same bits as from the gathered nodes.
Mat3 tet_deformation_gradient(const Mat83& dN_dX, const VecX& x, const std::array<int, 8>& nodes);

// hessian(a, b) += w sum_{j,m} dN_a,j dN_b,m H_jm over the first n nodes: w B^T H B for one
// point, without forming B. With n = 4 (a tet) node 0's blocks follow from the others'
// (its shape function gradient is minus their sum): equal up to round-off.
void add_point_hessian(const Mat83& dN, int n, const Mat9& H, double w, Mat24& hessian);
void add_point_hessian(const Mat83& dN, int n, const Mat9& H, double w, Mat12& hessian);

// +infinity when the material is undefined at some point (e.g. neo_hookean with J <= 0).
double hyperelastic_element_energy(const Material& material, const ElementQuadrature& quad,
                                   const ElementNodes& nodes);

// Returns the energy; writes the gradient and (if hessian != nullptr) the sum of the
// points' projected Hessians, which is positive semi-definite.
double hyperelastic_element_derivatives(const Material& material, const ElementQuadrature& quad,
                                        const ElementNodes& nodes, Vec24& gradient, Mat24* hessian);

// The same for a tet (nodes.count 4, no mean dilatation) in 12 x 12: the same code
// (sum_over_points), so the entries equal the padded version's bit for bit, without
// zeroing and scattering a 24 x 24 matrix that is three-quarters padding.
// given: the tet's F (deformation_gradient(quad.dN_dX[0], nodes)) and its SVD (or null: F
// alone, a tet whose Hessian is kept), when the caller has them (a batch,
// hyperelastic_batches.hpp): the same results, bit for bit.
struct GivenDeformation {
  const Mat3& F;
  const RotationVariantSvd* svd;
};
double hyperelastic_tet_derivatives(const Material& material, const ElementQuadrature& quad,
                                    const ElementNodes& nodes, Vec12& gradient, Mat12* hessian,
                                    const GivenDeformation* given = nullptr);
// The same with the projected Hessian added straight into a system matrix's values (the
// assembly's path: no 12 x 12 matrix formed and scattered; the same values bit for bit as
// scatter_element_matrix of the matrix above, as long as no value is -0: see
// tet_hessian_scatter.hpp). A one-point tet only (nodes.count 4, no mean dilatation).
double hyperelastic_tet_derivatives(const Material& material, const ElementQuadrature& quad,
                                    const ElementNodes& nodes, Vec12& gradient, const TetHessianScatter& hessian,
                                    const GivenDeformation* given = nullptr);

// Energy and gradient alone of a one-point tet of an invariant material at its F, shape
// gradients dN and weight (rest volume) w: the bits of
// hyperelastic_tet_derivatives without a Hessian, with none of its gathers and branches (the
// gradient passes of Newton's line search and of tets whose Hessian is kept).
double invariant_tet_energy_gradient(const InvariantMaterial& material, const Mat3& F, const Mat83& dN, double w,
                                     Vec12& gradient);

// The same with the exact Hessian d2Psi/dF2 (not projected; Newton near convergence), or the
// projected one where the material is undefined at some point (J <= 0 for neo_hookean; the
// energy is then +infinity). Padded (mean dilatation too) and tet versions.
double hyperelastic_element_exact_derivatives(const Material& material, const ElementQuadrature& quad,
                                              const ElementNodes& nodes, Vec24& gradient, Mat24& hessian);
double hyperelastic_tet_exact_derivatives(const Material& material, const ElementQuadrature& quad,
                                          const ElementNodes& nodes, Vec12& gradient, Mat12& hessian);

}  // namespace sinew
