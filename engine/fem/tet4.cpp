#include "engine/fem/tet4.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/fem/hex8.hpp"
#include "engine/geometry/tet_mesh.hpp"

namespace sinew {

Tet4Reference compute_tet4_reference(const std::array<Vec3, 4>& X,
                                     const IsotropicElasticity& elasticity) {
  Tet4Reference ref;
  ref.elasticity = elasticity;
  Mat3 Dm;
  for (int i = 0; i < 3; ++i) Dm.col(i) = X[i + 1] - X[0];
  const double det = Dm.determinant();
  double longest2 = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) longest2 = std::max(longest2, (X[a] - X[b]).squaredNorm());
  if (!(det > kDegenerateTet * longest2 * std::sqrt(longest2)))
    throw std::invalid_argument(
        "compute_tet4_reference: rest tet is degenerate or inverted (det Dm = " +
        std::to_string(det) + ")");
  ref.volume = det / 6;
  ref.Dm_inv = Dm.inverse();
  // grad N_i = row i of Dm^-1 (i = 1..3), grad N_0 = -(r1 + r2 + r3).
  ref.dN_dX.bottomRows<3>() = ref.Dm_inv;
  ref.dN_dX.row(0) = -ref.Dm_inv.colwise().sum();
  const Mat6x12 B = tet4_strain_displacement(ref);
  ref.Ke = ref.volume * B.transpose() * elasticity.voigt_matrix() * B;
  ref.Ke = 0.5 * (ref.Ke + ref.Ke.transpose()).eval();
  return ref;
}

Mat6x12 tet4_strain_displacement(const Tet4Reference& ref) {
  Mat6x12 B = Mat6x12::Zero();
  for (int n = 0; n < 4; ++n) {
    const double dx = ref.dN_dX(n, 0), dy = ref.dN_dX(n, 1), dz = ref.dN_dX(n, 2);
    B(0, 3 * n + 0) = dx;
    B(1, 3 * n + 1) = dy;
    B(2, 3 * n + 2) = dz;
    B(3, 3 * n + 0) = dy, B(3, 3 * n + 1) = dx;
    B(4, 3 * n + 1) = dz, B(4, 3 * n + 2) = dy;
    B(5, 3 * n + 2) = dx, B(5, 3 * n + 0) = dz;
  }
  return B;
}

Mat3 tet4_deformation_gradient(const Tet4Reference& ref, const std::array<Vec3, 4>& x) {
  Mat3 Ds;
  for (int i = 0; i < 3; ++i) Ds.col(i) = x[i + 1] - x[0];
  return Ds * ref.Dm_inv;
}

Mat3 compute_tet4_rotation(const Tet4Reference& ref, const std::array<Vec3, 4>& x) {
  return polar_rotation(tet4_deformation_gradient(ref, x));
}

Vec12 tet4_corotated_displacement(const Mat3& R, const std::array<Vec3, 4>& x,
                                  const std::array<Vec3, 4>& X) {
  Vec12 u;
  for (int n = 0; n < 4; ++n) u.segment<3>(3 * n) = R.transpose() * x[n] - X[n];
  return u;
}

Vec12 tet4_elastic_force(const Tet4Reference& ref, const Mat3& R, const Vec12& u) {
  const Vec12 local = ref.Ke * u;
  Vec12 f;
  for (int n = 0; n < 4; ++n) f.segment<3>(3 * n) = -R * local.segment<3>(3 * n);
  return f;
}

void tet4_warped_stiffness(const Tet4Reference& ref, const Mat3& R, Mat12& out) {
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      out.block<3, 3>(3 * a, 3 * b).noalias() =
          R * ref.Ke.block<3, 3>(3 * a, 3 * b) * R.transpose();
}

double tet4_limit_energy(const Tet4Reference& ref, const Vec12& u) { return u.dot(ref.Ke * u); }

}  // namespace sinew
