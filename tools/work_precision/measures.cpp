#include "tools/work_precision/measures.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/hyperelastic_element.hpp"

namespace sinew::wp {

double total_energy(const World& world) {
  const Model& m = world.model();
  const VecX& x = world.state().x;
  double energy = world.kinetic_energy();
  for (int n = 0; n < m.num_nodes; ++n) energy -= m.node_mass[n] * m.gravity.dot(x.segment<3>(3 * n));
  for (int e = 0; e < m.num_elements; ++e) {
    const ElementNodes nodes = gather_element_nodes(m, x, e);
    const Body& body = m.bodies[m.element_body[e]];
    if (body.hyperelastic)
      energy += hyperelastic_element_energy(*body.hyperelastic, element_quadrature(m, e), nodes);
    else
      energy += 0.5 * element_limit_energy(m, e, compute_corotated_element(m, e, nodes).u);  // Ue = u^T Ke u
  }
  return energy;
}

double axis_strain_excess(const World& world) {
  const Model& m = world.model();
  double worst = 0;
  for (int e = 0; e < m.num_elements; ++e) {
    const StrainLimitDesc& limit = m.bodies[m.element_body[e]].strain_limit;
    if (!limit.enabled) continue;
    const Mat3 F = element_center_deformation_gradient(m, e, gather_element_nodes(m, world.state().x, e));
    if (limit.mode == "isotropic") {  // the tightest limits on every principal stretch
      double lo = 0, hi = INFINITY;
      for (int j = 0; j < 3; ++j) {
        if (limit.smin[j] > 0) lo = std::max(lo, limit.smin[j]);
        if (std::isfinite(limit.smax[j])) hi = std::min(hi, limit.smax[j]);
      }
      const Vec3 s = Eigen::JacobiSVD<Mat3>(F).singularValues();
      worst = std::max({worst, lo - s.minCoeff(), s.maxCoeff() - hi});
      continue;
    }
    const Mat3& frame = m.element_strain_frame[e];
    for (int j = 0; j < 3; ++j) {
      const double stretch = (F * frame.col(j)).norm();
      if (limit.smin[j] > 0) worst = std::max(worst, limit.smin[j] - stretch);
      if (std::isfinite(limit.smax[j])) worst = std::max(worst, stretch - limit.smax[j]);
    }
  }
  return worst;
}

VolumeChange volume_change(const World& world) {
  const Model& m = world.model();
  VolumeChange r;
  double volume = 0, deformed = 0;
  for (int e = 0; e < m.num_elements; ++e) {
    const double J = element_center_deformation_gradient(m, e, gather_element_nodes(m, world.state().x, e)).determinant();
    const double V = element_rest_volume(m, e);
    r.worst = std::max(r.worst, std::abs(J - 1));
    volume += V;
    deformed += J * V;
  }
  r.total = volume > 0 ? deformed / volume - 1 : 0;
  return r;
}

}  // namespace sinew::wp
