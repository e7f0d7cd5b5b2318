#pragma once
// The trilinear hexahedron on a regular lattice (paper 000, section 3).
//
// Node n (0-based) = 4a + 2b + c has natural coordinates s_n = (2a-1, 2b-1, 2c-1)
// (paper: n = 4(i-1) + 2(j-1) + k, s_n = ((-1)^i, (-1)^j, (-1)^k)). Shape functions
// N_n(s) = (1 + s_n1 s1)(1 + s_n2 s2)(1 + s_n3 s3) / 8 (eq. 5). On a regular lattice of
// cell size c the map from natural to material coordinates is X = X0 + (c/2) s, so
// dN/dX = (2/c) dN/ds and det(dX/ds) = (c/2)^3 (eqs. 6-10).
#include <Eigen/Core>
#include <array>

#include "engine/core/types.hpp"
#include "engine/fem/isotropic_elasticity.hpp"
#include "engine/math/polar_rotation.hpp"

namespace sinew {

using Mat24 = Eigen::Matrix<double, 24, 24>;
using Vec24 = Eigen::Matrix<double, 24, 1>;
using Mat83 = Eigen::Matrix<double, 8, 3>;
using Mat6x24 = Eigen::Matrix<double, 6, 24>;

inline Vec3 hex8_natural_node(int n) {
  return Vec3(2.0 * ((n >> 2) & 1) - 1, 2.0 * ((n >> 1) & 1) - 1, 2.0 * (n & 1) - 1);
}

// Shape functions and their natural derivatives (eq. 5; H(s) of eq. 7 is the 8x3 matrix).
std::array<double, 8> hex8_shape(const Vec3& s);
Mat83 hex8_shape_derivatives(const Vec3& s);

// Gauss points s_q = (+-1/sqrt 3, ...), weights 1, in the paper's order (eq. 8).
Vec3 hex8_gauss_point(int q);

// Everything an element of one cell size and material needs, computed once (eq. 10).
struct Hex8Reference {
  double cell_size = 0;
  IsotropicElasticity elasticity;
  double det_dXds = 0;              // (c/2)^3, the volume weight of each Gauss point
  std::array<Mat83, 8> dN_dX;       // H(s_q) F^-1 at each Gauss point
  std::array<Mat6x24, 8> B;         // Voigt strain-displacement matrix at each Gauss point
  Mat24 Ke;                         // sum_q B^T C B det(F)
  double root_lambda_max = 0;       // sqrt of Ke's largest eigenvalue (energy_screen.hpp)
};
Hex8Reference compute_hex8_reference(double cell_size, const IsotropicElasticity& elasticity);

// Element rotation: polar decomposition of the deformation gradient of the innermost
// tetrahedron of the cell (nodes 0, 3, 5, 6: the even-parity corners; paper 000, fig. 2,
// after [NL08]). x holds the 8 deformed node positions; the rest tetrahedron is regular.
Mat3 compute_hex8_rotation(const std::array<Vec3, 8>& x, double cell_size);
// That tetrahedron's deformation gradient, whose polar part the rotation is. Its inverse
// rest edge matrix has 2-norm 1 / cell_size.
Mat3 hex8_inner_deformation_gradient(const std::array<Vec3, 8>& x, double cell_size);

// Corotated displacement u = R^T x - X (24-vector, node-major).
Vec24 hex8_corotated_displacement(const Mat3& R, const std::array<Vec3, 8>& x,
                                  const std::array<Vec3, 8>& X);

// Elastic force on the 8 nodes: f = -R Ke (R^T x - X) (warped stiffness, [MG04]).
Vec24 hex8_elastic_force(const Hex8Reference& ref, const Mat3& R, const Vec24& u);

// Warped stiffness R Ke R^T (the 3x3 blocks rotated), the force Jacobian with R frozen.
void hex8_warped_stiffness(const Hex8Reference& ref, const Mat3& R, Mat24& out);

// Element energy of paper 000, eq. 13: Ue = sum_q e(eps_q) det(F) with e = sigma : eps,
// which equals u^T Ke u (twice the stored elastic energy 1/2 u^T Ke u).
double hex8_limit_energy(const Hex8Reference& ref, const Vec24& u);

// Deformation gradient at natural point s from node positions.
Mat3 hex8_deformation_gradient(const Hex8Reference& ref, const std::array<Vec3, 8>& x,
                               const Vec3& s);

}  // namespace sinew
