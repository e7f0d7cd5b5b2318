#pragma once
// The linear tetrahedron, corotational (paper 001, sec. 3.1, after [MG04]), with the
// Hookean material of hex8 (paper 000, eq. 1).
//
// Rest edge matrix Dm = [X1-X0, X2-X0, X3-X0], V = det(Dm) / 6 > 0. The barycentric
// coordinates are xi = Dm^-1 (X - X0), so grad N_i (i = 1..3) is row i of Dm^-1 and
// grad N_0 = -(sum of the rows) (paper 001 eqs. 1-3: its rows r1, r2, r3 and the fictitious
// r4 = -(r1 + r2 + r3), with x4 as the base node where here it is x0).
// F = Ds Dm^-1 = sum_n x_n grad N_n^T is constant in the tet; so are strain and stress, and
// Ke = V B^T C B (one-point integration is exact).
#include <Eigen/Core>
#include <array>

#include "engine/core/types.hpp"
#include "engine/fem/isotropic_elasticity.hpp"

namespace sinew {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat6x12 = Eigen::Matrix<double, 6, 12>;

// Everything one rest tet needs, computed once.
struct Tet4Reference {
  IsotropicElasticity elasticity;
  double volume = 0;                  // V = det(Dm) / 6
  Mat3 Dm_inv;                        // inverse rest edge matrix
  Eigen::Matrix<double, 4, 3> dN_dX;  // row n = grad N_n
  Eigen::Matrix<double, 12, 12> Ke;   // V B^T C B
};

// Throws std::invalid_argument when the rest tet is degenerate or inverted
// (6 V <= 1e-12 L^3, L the longest edge; see kDegenerateTet in tet_mesh.hpp).
Tet4Reference compute_tet4_reference(const std::array<Vec3, 4>& X,
                                     const IsotropicElasticity& elasticity);

// Voigt strain-displacement matrix (rows eps_xx, eps_yy, eps_zz, gamma_xy, gamma_yz,
// gamma_zx, as hex8): eps = B u for the 12-vector u of nodal displacements.
Mat6x12 tet4_strain_displacement(const Tet4Reference& ref);

// F = Ds Dm^-1 with Ds = [x1-x0, x2-x0, x3-x0] (paper 001 eq. 3).
Mat3 tet4_deformation_gradient(const Tet4Reference& ref, const std::array<Vec3, 4>& x);

// Element rotation: polar_rotation(F) (engine/math/polar_rotation.hpp), F = R S with det R = +1 ([MG04]).
Mat3 compute_tet4_rotation(const Tet4Reference& ref, const std::array<Vec3, 4>& x);

// Corotated displacement u = R^T x - X (12-vector, node-major).
Vec12 tet4_corotated_displacement(const Mat3& R, const std::array<Vec3, 4>& x,
                                  const std::array<Vec3, 4>& X);

// Elastic force on the 4 nodes: f = -R Ke (R^T x - X) (warped stiffness, [MG04]).
Vec12 tet4_elastic_force(const Tet4Reference& ref, const Mat3& R, const Vec12& u);

// Warped stiffness R Ke R^T (3x3 blocks rotated), the force Jacobian with R frozen.
void tet4_warped_stiffness(const Tet4Reference& ref, const Mat3& R, Mat12& out);

// Energy of paper 000, eq. 13 as for hex8: Ue = sigma : eps V = u^T Ke u (twice the stored
// elastic energy 1/2 u^T Ke u).
double tet4_limit_energy(const Tet4Reference& ref, const Vec12& u);

}  // namespace sinew
