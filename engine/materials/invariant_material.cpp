#include "engine/materials/invariant_material.hpp"

#include <Eigen/Geometry>

namespace sinew {

namespace {

Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

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

Mat9 cofactor_hessian(const Mat3& F) {
  Mat9 H = Mat9::Zero();
  const Mat3 b01 = -cross_matrix(F.col(2));
  const Mat3 b02 = cross_matrix(F.col(1));
  const Mat3 b12 = -cross_matrix(F.col(0));
  H.block<3, 3>(0, 3) = b01;
  H.block<3, 3>(3, 0) = b01.transpose();
  H.block<3, 3>(0, 6) = b02;
  H.block<3, 3>(6, 0) = b02.transpose();
  H.block<3, 3>(3, 6) = b12;
  H.block<3, 3>(6, 3) = b12.transpose();
  return H;
}

double InvariantMaterial::energy(const Mat3& F) const { return terms_at(*this, F).psi; }

Mat3 InvariantMaterial::pk1(const Mat3& F) const {
  const InvariantTerms t = terms_at(*this, F);
  return 2 * t.f1 * F + t.g1 * cofactor_matrix(F);
}

Mat9 InvariantMaterial::hessian(const Mat3& F) const { return invariant_hessian(F, terms_at(*this, F)); }

// Entry by entry in one pass over H: the two outer products and the diagonal, then g' H_J's
// 36 non-zeros (the 9 x 9 temporaries of the matrix expression took twice as long; it runs
// once per tet and Newton iteration).
Mat9 invariant_hessian(const Mat3& F, const InvariantTerms& t) {
  const Vec9 f = vec9(F), c = vec9(cofactor_matrix(F));
  const Vec9 f_scaled = 4 * t.f2 * f, c_scaled = t.g2 * c;
  Mat9 H;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) H(i, j) = f_scaled[i] * f[j] + c_scaled[i] * c[j];
  H.diagonal().array() += 2 * t.f1;
  // g' H_J: block (a, b) of H_J is [s f_k]x with (a, b, k) a cyclic or anticyclic order of
  // (0, 1, 2) and s = +1 for (0, 2, 1), (1, 0, 2), (2, 1, 0), else -1 (cofactor_hessian).
  const auto add_cross = [&](int a, int b, const Vec3& col, double scale) {
    const Vec3 v = scale * col;  // [v]x into block (a, b), its transpose into (b, a)
    const int r = 3 * a, q = 3 * b;
    H(r + 0, q + 1) -= v.z(), H(r + 0, q + 2) += v.y();
    H(r + 1, q + 0) += v.z(), H(r + 1, q + 2) -= v.x();
    H(r + 2, q + 0) -= v.y(), H(r + 2, q + 1) += v.x();
    H(q + 1, r + 0) -= v.z(), H(q + 2, r + 0) += v.y();
    H(q + 0, r + 1) += v.z(), H(q + 2, r + 1) -= v.x();
    H(q + 0, r + 2) -= v.y(), H(q + 1, r + 2) += v.x();
  };
  add_cross(0, 1, F.col(2), -t.g1);
  add_cross(0, 2, F.col(1), t.g1);
  add_cross(1, 2, F.col(0), -t.g1);
  return H;
}

Mat9 InvariantMaterial::projected_hessian(const Mat3& F) const {
  const InvariantTerms t = terms_at(*this, F);  // once for both: a log and two divisions (stable)
  return remove_negative_modes(invariant_hessian(F, t), invariant_eigensystem(F, t));
}

SvdEigensystem InvariantMaterial::eigensystem(const Mat3& F) const {
  return invariant_eigensystem(F, terms_at(*this, F));
}

SvdEigensystem invariant_eigensystem(const Mat3& F, const InvariantTerms& t) {
  SvdEigensystem system{compute_rotation_variant_svd(F)};
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
