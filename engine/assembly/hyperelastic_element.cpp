#include "engine/assembly/hyperelastic_element.hpp"

#include <limits>

namespace sinew {
namespace {

Mat3 deformation_gradient(const Mat83& dN_dX, const ElementNodes& nodes) {
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < nodes.count; ++a) F += nodes.x[a] * dN_dX.row(a);
  return F;
}

}  // namespace

double hyperelastic_element_energy(const Material& material, const ElementQuadrature& quad,
                                   const ElementNodes& nodes) {
  double energy = 0;
  for (int q = 0; q < quad.points; ++q) {
    const Mat3 F = deformation_gradient(quad.dN_dX[q], nodes);
    if (!material.is_defined(F)) return std::numeric_limits<double>::infinity();
    energy += quad.weight * material.energy(F);
  }
  return energy;
}

double hyperelastic_element_derivatives(const Material& material, const ElementQuadrature& quad,
                                        const ElementNodes& nodes, Vec24& gradient, Mat24* hessian) {
  double energy = 0;
  gradient.setZero();
  if (hessian) hessian->setZero();
  const int n = nodes.count;
  Eigen::Matrix<double, 9, 24> B;
  for (int q = 0; q < quad.points; ++q) {
    const Mat83& dN = quad.dN_dX[q];
    const Mat3 F = deformation_gradient(dN, nodes);
    if (!material.is_defined(F)) energy = std::numeric_limits<double>::infinity();
    else energy += quad.weight * material.energy(F);
    const Mat3 P = material.pk1(F);
    for (int a = 0; a < n; ++a) gradient.segment<3>(3 * a) += quad.weight * (P * dN.row(a).transpose());
    if (!hessian) continue;
    B.setZero();
    for (int a = 0; a < n; ++a)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) B(i + 3 * j, 3 * a + i) = dN(a, j);
    const Mat9 H = material.projected_hessian(F);
    hessian->noalias() += quad.weight * (B.transpose() * H * B);
  }
  return energy;
}

}  // namespace sinew
