#include "engine/materials/invariant_material.hpp"

#include <Eigen/Geometry>

namespace sinew {

Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

namespace {

InvariantTerms terms_at(const InvariantMaterial& material, const Mat3& F) {
  return material.terms(F.squaredNorm(), F.determinant());
}

}  // namespace

Mat3 cofactor_matrix(const Mat3& F) {
  Mat3 c;
  c.col(0) = F.col(1).cross(F.col(2));
  c.col(1) = F.col(2).cross(F.col(0));
  c.col(2) = F.col(0).cross(F.col(1));
  return c;
}

void add_cofactor_hessian(const Mat3& F, double scale, Mat9& H) {
  const Mat3 b01 = -scale * cross_matrix(F.col(2));
  const Mat3 b02 = scale * cross_matrix(F.col(1));
  const Mat3 b12 = -scale * cross_matrix(F.col(0));
  H.block<3, 3>(0, 3) += b01;
  H.block<3, 3>(3, 0) += b01.transpose();
  H.block<3, 3>(0, 6) += b02;
  H.block<3, 3>(6, 0) += b02.transpose();
  H.block<3, 3>(3, 6) += b12;
  H.block<3, 3>(6, 3) += b12.transpose();
}

Mat9 cofactor_hessian(const Mat3& F) {
  Mat9 H = Mat9::Zero();
  add_cofactor_hessian(F, 1.0, H);
  return H;
}

double InvariantMaterial::energy(const Mat3& F) const { return terms_at(*this, F).psi; }

Mat3 InvariantMaterial::pk1(const Mat3& F) const { return invariant_pk1(F, terms_at(*this, F)); }

Mat3 invariant_pk1(const Mat3& F, const InvariantTerms& t) { return 2 * t.f1 * F + t.g1 * cofactor_matrix(F); }

Mat9 InvariantMaterial::hessian(const Mat3& F) const { return invariant_hessian(F, terms_at(*this, F)); }

// Entry by entry in one pass over H: the two outer products and the diagonal, then g' H_J
// block by block (the 9 x 9 temporaries of the matrix expression took twice as long; it runs
// once per tet and Newton iteration).
Mat9 invariant_hessian(const Mat3& F, const InvariantTerms& t) {
  const Vec9 f = vec9(F), c = vec9(cofactor_matrix(F));
  const Vec9 f_scaled = 4 * t.f2 * f, c_scaled = t.g2 * c;
  Mat9 H;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) H(i, j) = f_scaled[i] * f[j] + c_scaled[i] * c[j];
  H.diagonal().array() += 2 * t.f1;
  add_cofactor_hessian(F, t.g1, H);
  return H;
}

Mat9 InvariantMaterial::projected_hessian(const Mat3& F) const {
  return invariant_projected_hessian(F, terms_at(*this, F));  // the terms once for both parts
}

Mat9 invariant_projected_hessian(const Mat3& F, const InvariantTerms& t) {
  return remove_negative_modes(invariant_hessian(F, t), invariant_eigensystem(F, t));
}

SvdEigensystem InvariantMaterial::eigensystem(const Mat3& F) const {
  return invariant_eigensystem(F, terms_at(*this, F));
}

SvdEigensystem invariant_eigensystem(const Mat3& F, const InvariantTerms& t, const RotationVariantSvd* svd) {
  SvdEigensystem system{svd ? *svd : compute_rotation_variant_svd(F)};
  const Vec3& s = system.svd.S;
  const Vec3 c(s(1) * s(2), s(0) * s(2), s(0) * s(1));
  for (int k = 0; k < 3; ++k) {
    system.twist(k) = 2 * t.f1 + t.g1 * s(k);
    system.flip(k) = 2 * t.f1 - t.g1 * s(k);
  }
  system.scaling = 4 * t.f2 * s * s.transpose() + t.g2 * c * c.transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      system.scaling(i, j) += i == j ? 2 * t.f1 : t.g1 * s(3 - i - j);
  return system;
}

}  // namespace sinew
