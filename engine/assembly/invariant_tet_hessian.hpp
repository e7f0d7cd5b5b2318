#pragma once
// The Hessian of an invariant material (Psi = f(Ic) + g(J), invariant_material.hpp) at a
// tet's one point, w B^T H B, term by term in 12 x 12 without forming the 9 x 9 H:
//   H = 2 f' I_9 + 4 f'' vec(F) vec(F)^T + g'' vec(cof F) vec(cof F)^T + g' H_J
//       - sum over the negative modes of value_m vec(Q_m) vec(Q_m)^T   (when projected)
// and B^T vec(Y) gives node a the vector Y dN_a, so block (a, b) of the result is
//   w [2 f' (dN_a . dN_b) I + 4 f'' u_a u_b^T + g'' z_a z_b^T - g' [F (dN_a x dN_b)]x
//      - sum_m value_m p_ma p_mb^T]
// with u_a = F dN_a, z_a = cof(F) dN_a, p_ma = Q_m dN_a and [v]x the cross-product matrix
// (the 3 x 3 block (j, m) of H_J is -sum_k eps_jmk [f_k]x, f_k the columns of F). About
// 700 flops against 1,500 for H and the general congruence (add_point_hessian).
#include "engine/assembly/tet_hessian_scatter.hpp"
#include "engine/fem/hex8.hpp"
#include "engine/fem/tet4.hpp"
#include "engine/materials/invariant_material.hpp"

namespace sinew {

// hessian += w B^T H B for a tet's shape function gradients dN (rows 0-3; they sum to zero),
// H the exact Hessian for the terms t when `project` is false, else that Hessian without the
// negative modes of invariant_eigensystem(F, t) (InvariantMaterial::projected_hessian).
// svd: F's, when the caller has it (invariant_eigensystem).
void add_invariant_tet_hessian(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                               Mat12& hessian, const RotationVariantSvd* svd = nullptr);
// The same added straight into a system matrix's values (tet_hessian_scatter.hpp).
void add_invariant_tet_hessian(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                               const TetHessianScatter& hessian, const RotationVariantSvd* svd = nullptr);

}  // namespace sinew
