#include "engine/fem/hex8.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

namespace sinew {

std::array<double, 8> hex8_shape(const Vec3& s) {
  std::array<double, 8> N;
  for (int n = 0; n < 8; ++n) {
    const Vec3 sn = hex8_natural_node(n);
    N[n] = (1 + sn.x() * s.x()) * (1 + sn.y() * s.y()) * (1 + sn.z() * s.z()) / 8;
  }
  return N;
}

Mat83 hex8_shape_derivatives(const Vec3& s) {
  Mat83 H;
  for (int n = 0; n < 8; ++n) {
    const Vec3 sn = hex8_natural_node(n);
    const Vec3 f(1 + sn.x() * s.x(), 1 + sn.y() * s.y(), 1 + sn.z() * s.z());
    H(n, 0) = sn.x() * f.y() * f.z() / 8;
    H(n, 1) = f.x() * sn.y() * f.z() / 8;
    H(n, 2) = f.x() * f.y() * sn.z() / 8;
  }
  return H;
}

Vec3 hex8_gauss_point(int q) { return hex8_natural_node(q) / std::sqrt(3.0); }

Hex8Reference compute_hex8_reference(double cell_size, const IsotropicElasticity& elasticity) {
  Hex8Reference ref;
  ref.cell_size = cell_size;
  ref.elasticity = elasticity;
  ref.det_dXds = std::pow(cell_size / 2, 3);
  const Eigen::Matrix<double, 6, 6> C = elasticity.voigt_matrix();
  ref.Ke.setZero();
  for (int q = 0; q < 8; ++q) {
    ref.dN_dX[q] = hex8_shape_derivatives(hex8_gauss_point(q)) * (2 / cell_size);
    // Voigt rows: eps_xx, eps_yy, eps_zz, gamma_xy, gamma_yz, gamma_zx.
    Mat6x24& B = ref.B[q];
    B.setZero();
    for (int n = 0; n < 8; ++n) {
      const double dx = ref.dN_dX[q](n, 0), dy = ref.dN_dX[q](n, 1), dz = ref.dN_dX[q](n, 2);
      B(0, 3 * n + 0) = dx;
      B(1, 3 * n + 1) = dy;
      B(2, 3 * n + 2) = dz;
      B(3, 3 * n + 0) = dy, B(3, 3 * n + 1) = dx;
      B(4, 3 * n + 1) = dz, B(4, 3 * n + 2) = dy;
      B(5, 3 * n + 2) = dx, B(5, 3 * n + 0) = dz;
    }
    ref.Ke += B.transpose() * C * B * ref.det_dXds;  // eq. 10, w_q = 1
  }
  ref.Ke = 0.5 * (ref.Ke + ref.Ke.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Mat24> eigen(ref.Ke, Eigen::EigenvaluesOnly);
  ref.root_lambda_max = std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
  return ref;
}

Mat3 hex8_inner_deformation_gradient(const std::array<Vec3, 8>& x, double cell_size) {
  // Innermost tetrahedron: corners (0,0,0), (0,1,1), (1,0,1), (1,1,0) = nodes 0, 3, 5, 6.
  // At rest its edge matrix is c * [(0,1,1) (1,0,1) (1,1,0)], whose inverse is
  // (1/(2c)) * [[-1,1,1],[1,-1,1],[1,1,-1]].
  Mat3 Ds;
  Ds.col(0) = x[3] - x[0];
  Ds.col(1) = x[5] - x[0];
  Ds.col(2) = x[6] - x[0];
  Mat3 Dm_inv;
  Dm_inv << -1, 1, 1, 1, -1, 1, 1, 1, -1;
  Dm_inv /= 2 * cell_size;
  return Ds * Dm_inv;
}

Mat3 compute_hex8_rotation(const std::array<Vec3, 8>& x, double cell_size) {
  return polar_rotation(hex8_inner_deformation_gradient(x, cell_size));
}

Vec24 hex8_corotated_displacement(const Mat3& R, const std::array<Vec3, 8>& x,
                                  const std::array<Vec3, 8>& X) {
  Vec24 u;
  for (int n = 0; n < 8; ++n) u.segment<3>(3 * n) = R.transpose() * x[n] - X[n];
  return u;
}

Vec24 hex8_elastic_force(const Hex8Reference& ref, const Mat3& R, const Vec24& u) {
  const Vec24 local = ref.Ke * u;
  Vec24 f;
  for (int n = 0; n < 8; ++n) f.segment<3>(3 * n) = -R * local.segment<3>(3 * n);
  return f;
}

void hex8_warped_stiffness(const Hex8Reference& ref, const Mat3& R, Mat24& out) {
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      out.block<3, 3>(3 * a, 3 * b).noalias() =
          R * ref.Ke.block<3, 3>(3 * a, 3 * b) * R.transpose();
}

double hex8_limit_energy(const Hex8Reference& ref, const Vec24& u) {
  return u.dot(ref.Ke * u);
}

Mat3 hex8_deformation_gradient(const Hex8Reference& ref, const std::array<Vec3, 8>& x,
                               const Vec3& s) {
  const Mat83 dN = hex8_shape_derivatives(s) * (2 / ref.cell_size);
  Mat3 F = Mat3::Zero();
  for (int n = 0; n < 8; ++n) F += x[n] * dN.row(n);
  return F;
}

}  // namespace sinew
