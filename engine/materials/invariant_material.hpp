#pragma once
// Materials of the form Psi(F) = f(Ic) + g(J), Ic = tr(F^T F), J = det F: stable and classic
// Neo-Hookean, Fung, Arruda-Boyce (paper 003, secs. 3-4 and 7: the analysis "supports any model
// formulated in terms of the first and third invariants"). With cof(F) = dJ/dF and
// H_J = d^2 J / dF^2 (linear in F):
//   P = 2 f' F + g' cof(F)
//   H = 2 f' I_9 + 4 f'' vec(F) vec(F)^T + g'' vec(cof F) vec(cof F)^T + g' H_J
// and in the SVD frame (psi_i = 2 f' sigma_i + g' sigma_j sigma_k; paper 003, sec. 4.5):
//   twist_k = 2 f' + g' sigma_k,   flip_k = 2 f' - g' sigma_k,
//   scaling_ij = 2 f' delta_ij + 4 f'' sigma_i sigma_j + g'' c_i c_j + g' (1 - delta_ij) sigma_k,
// c_i = dJ / dsigma_i = sigma_j sigma_k. No division anywhere: finite for every finite F.
#include "engine/materials/isotropic_material.hpp"

namespace sinew {

// [a]x, the matrix of b -> a x b.
Mat3 cross_matrix(const Vec3& a);
// dJ/dF = [f1 x f2, f2 x f0, f0 x f1] (columns f_a of F).
Mat3 cofactor_matrix(const Mat3& F);

// d^2 J / dF^2: 3x3 blocks (a, b) = d^2 J / df_a df_b; zero diagonal blocks,
// (0, 1) = -[f2]x, (0, 2) = [f1]x, (1, 2) = -[f0]x, symmetric.
Mat9 cofactor_hessian(const Mat3& F);
// H += scale * cofactor_hessian(F), block by block (no 9 x 9 temporary).
void add_cofactor_hessian(const Mat3& F, double scale, Mat9& H);

// f(Ic) + g(J) and the four derivatives the formulas above need, at one (Ic, J).
struct InvariantTerms {
  double psi = 0;  // f(Ic) + g(J)
  double f1 = 0;  // f'(Ic)
  double f2 = 0;  // f''(Ic)
  double g1 = 0;  // g'(J)
  double g2 = 0;  // g''(J)
};

// The Hessian above and its closed-form eigensystem for given terms (which need not come from
// one (Ic, J): mean dilatation takes g' at the element's mean J).
Mat3 invariant_pk1(const Mat3& F, const InvariantTerms& t);
Mat9 invariant_hessian(const Mat3& F, const InvariantTerms& t);
Mat9 invariant_projected_hessian(const Mat3& F, const InvariantTerms& t);  // without its negative modes
// svd: F's, when the caller has it (compute_rotation_variant_svds for a batch): the same
// result, bit for bit.
SvdEigensystem invariant_eigensystem(const Mat3& F, const InvariantTerms& t, const RotationVariantSvd* svd = nullptr);

class InvariantMaterial : public IsotropicMaterial {
 public:
  // final: the element assembly takes an invariant material's terms() directly
  // (hyperelastic_element.cpp), so an override of these would go unused there.
  double energy(const Mat3& F) const final;
  Mat3 pk1(const Mat3& F) const final;
  Mat9 hessian(const Mat3& F) const final;
  SvdEigensystem eigensystem(const Mat3& F) const override;
  // hessian(F) without its negative modes: cheaper than assembling all nine.
  Mat9 projected_hessian(const Mat3& F) const final;
  const InvariantMaterial* as_invariant() const final { return this; }
  // The material's f, g and derivatives (public so tests can check them directly).
  virtual InvariantTerms terms(double Ic, double J) const = 0;
};

}  // namespace sinew
