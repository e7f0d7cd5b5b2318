#include "engine/assembly/invariant_tet_hessian.hpp"

#include <Eigen/Geometry>

#include "engine/assembly/invariant_tet_blocks.hpp"
#include "engine/core/cpu_features.hpp"
#include "engine/materials/eigen_projection.hpp"

namespace sinew {

namespace {

// What both paths (the scalar one below, the AVX2 one in add_invariant_tet_hessian) take from
// F, the material's terms and the shape function gradients.
struct TetHessianInputs {
  NegativeModes modes;
  int mode_count = 0;
  Mat3 cofactor;
  double c_identity = 0, c_f = 0, c_cofactor = 0, c_cross = 0;
  Vec3 d[3];  // dN_a of nodes 1-3 (node 0's blocks follow from theirs)
};

TetHessianInputs tet_hessian_inputs(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                                    const RotationVariantSvd* svd) {
  TetHessianInputs in;
  in.mode_count = project ? negative_modes(invariant_eigensystem(F, t, svd), in.modes) : 0;
  in.cofactor = cofactor_matrix(F);
  in.c_identity = 2 * t.f1 * w, in.c_f = 4 * t.f2 * w, in.c_cofactor = t.g2 * w, in.c_cross = -t.g1 * w;
  for (int a = 0; a < 3; ++a) in.d[a] = dN.row(a + 1).transpose();
  return in;
}

template <class Sink>
void add_invariant_tet_hessian_to(const Mat3& F, const InvariantTerms& t, bool project, const Mat83& dN, double w,
                                  Sink& hessian, const RotationVariantSvd* svd) {
  const TetHessianInputs in = tet_hessian_inputs(F, t, project, dN, w, svd);
  const NegativeModes& modes = in.modes;
  const int mode_count = in.mode_count;
  const Vec3(&d)[3] = in.d;
  const double c_identity = in.c_identity, c_f = in.c_f, c_cofactor = in.c_cofactor, c_cross = in.c_cross;
  // Per node 1-3: the vectors above.
  Vec3 u[3], z[3], p[9][3];
  for (int a = 0; a < 3; ++a) {
    u[a] = times(F, d[a]);
    z[a] = times(in.cofactor, d[a]);
    for (int m = 0; m < mode_count; ++m) p[m][a] = times(modes.matrices[m], d[a]);
  }
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
  const TetHessianInputs in = tet_hessian_inputs(F, t, project, dN, w, svd);
  InvariantTetBlockTerms terms;
  terms.modes = in.mode_count;
  terms.c_cross = in.c_cross;
  fill_node_vectors_avx2(F, in.cofactor, dN, in.modes, w, in.c_f, in.c_cofactor, terms);
  const auto put = [](double (&to)[4], const Vec3& v) { to[0] = v[0], to[1] = v[1], to[2] = v[2], to[3] = 0; };
  for (int a = 0, pair = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      terms.diagonal[a][b] = in.c_identity * in.d[a].dot(in.d[b]);
      if (b == a) continue;
      const Mat3 cross = cross_matrix(F * in.d[a].cross(in.d[b]));
      for (int c = 0; c < 3; ++c) put(terms.cross_matrix[pair][c], cross.col(c));
      ++pair;
    }
  scatter_invariant_tet_blocks_avx2(terms, hessian);
}

}  // namespace sinew
