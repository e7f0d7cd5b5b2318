#include "engine/assembly/invariant_tet_hessian.hpp"

#include <Eigen/Geometry>

#include "engine/assembly/invariant_tet_blocks.hpp"
#include "engine/core/cpu_features.hpp"
#include "engine/materials/eigen_projection.hpp"

namespace sinew {

namespace {

template <class Sink>
void add_invariant_tet_hessian_to(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                                  Sink& hessian, const RotationVariantSvd* svd) {
  NegativeModes modes;
  const int mode_count = project ? negative_modes(invariant_eigensystem(F, t, svd), modes) : 0;
  const Mat3 cofactor = cofactor_matrix(F);
  // Per node 1-3 (node 0's blocks follow from theirs below): dN_a and the vectors above.
  Vec3 d[3], u[3], z[3], p[9][3];
  for (int a = 0; a < 3; ++a) {
    d[a] = dN.row(a + 1).transpose();
    u[a] = times(F, d[a]);
    z[a] = times(cofactor, d[a]);
    for (int m = 0; m < mode_count; ++m) p[m][a] = times(modes.matrices[m], d[a]);
  }
  const double c_identity = 2 * t.f1 * w, c_f = 4 * t.f2 * w, c_cofactor = t.g2 * w, c_cross = -t.g1 * w;
  Mat3 K[3][3];  // blocks of nodes 1-3
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      Mat3 block = c_f * u[a] * u[b].transpose() + c_cofactor * z[a] * z[b].transpose();
      block.diagonal().array() += c_identity * d[a].dot(d[b]);
      if (b != a) block += c_cross * cross_matrix(F * d[a].cross(d[b]));
      for (int m = 0; m < mode_count; ++m) block -= (w * modes.values[m]) * p[m][a] * p[m][b].transpose();
      K[a][b] = block;
      if (b != a) K[b][a] = block.transpose();
    }
  // dN_0 = -(dN_1 + dN_2 + dN_3), and every term is bilinear in (dN_a, dN_b): K_0b = -sum_a K_ab.
  Mat3 K0[3];
  for (int b = 0; b < 3; ++b) K0[b] = -(K[0][b] + K[1][b] + K[2][b]);
  add_tet_blocks(K, K0, hessian);
}

}  // namespace

void add_invariant_tet_hessian(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                               Mat12& hessian, const RotationVariantSvd* svd) {
  add_invariant_tet_hessian_to(F, t, project, dN, w, hessian, svd);
}

void add_invariant_tet_hessian(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                               const TetHessianScatter& hessian, const RotationVariantSvd* svd) {
  if (!use_avx2()) return add_invariant_tet_hessian_to(F, t, project, dN, w, hessian, svd);
  // The terms as add_invariant_tet_hessian_to takes them (the vectors u, z, p by times() in
  // AVX2, the dot and cross products by the same expressions: the same bits); the blocks in
  // AVX2 (invariant_tet_blocks.hpp). The bunny_5 Hessian pass,
  // callgrind: this function ~3,100 -> ~2,530 instructions a tet (modes included).
  NegativeModes modes;
  InvariantTetBlockTerms terms;
  terms.modes = project ? negative_modes(invariant_eigensystem(F, t, svd), modes) : 0;
  const Mat3 cofactor = cofactor_matrix(F);
  const double c_identity = 2 * t.f1 * w, c_f = 4 * t.f2 * w, c_cofactor = t.g2 * w;
  terms.c_cross = -t.g1 * w;
  fill_node_vectors_avx2(F, cofactor, dN, modes, w, c_f, c_cofactor, terms);
  Vec3 d[3];
  for (int a = 0; a < 3; ++a) d[a] = dN.row(a + 1).transpose();
  const auto put = [](double (&to)[4], const Vec3& v) { to[0] = v[0], to[1] = v[1], to[2] = v[2], to[3] = 0; };
  for (int a = 0, pair = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      terms.diagonal[a][b] = c_identity * d[a].dot(d[b]);
      if (b == a) continue;
      const Mat3 cross = cross_matrix(F * d[a].cross(d[b]));
      for (int c = 0; c < 3; ++c) put(terms.cross_matrix[pair][c], cross.col(c));
      ++pair;
    }
  scatter_invariant_tet_blocks_avx2(terms, hessian);
}

}  // namespace sinew
