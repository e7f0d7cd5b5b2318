#include "engine/analysis/element_fields.hpp"

#include <Eigen/LU>
#include <cmath>

namespace sinew {

Vec24 element_corotated_displacement(const Model& model, const VecX& x, int e, Mat3* rotation) {
  const auto& nodes = model.element_nodes[e];
  const Hex8Reference& ref = model.references[model.element_reference[e]];
  std::array<Vec3, 8> xe, Xe;
  for (int a = 0; a < 8; ++a) {
    xe[a] = x.segment<3>(3 * nodes[a]);
    Xe[a] = model.rest_x.segment<3>(3 * nodes[a]);
  }
  const Mat3 R = compute_hex8_rotation(xe, ref.cell_size);
  if (rotation) *rotation = R;
  return hex8_corotated_displacement(R, xe, Xe);
}

std::map<std::string, std::vector<double>> compute_element_fields(const Model& model, const State& state) {
  std::vector<double> density(model.num_elements), ratio(model.num_elements), energy(model.num_elements);
  for (int e = 0; e < model.num_elements; ++e) {
    const Hex8Reference& ref = model.references[model.element_reference[e]];
    const Vec24 u = element_corotated_displacement(model, state.x, e);
    const double Ue = hex8_limit_energy(ref, u);
    density[e] = 0.5 * Ue / std::pow(ref.cell_size, 3);
    energy[e] = model.element_Umax[e] > 0 ? Ue / model.element_Umax[e] : 0.0;
    std::array<Vec3, 8> xe;
    for (int a = 0; a < 8; ++a) xe[a] = state.x.segment<3>(3 * model.element_nodes[e][a]);
    ratio[e] = hex8_deformation_gradient(ref, xe, Vec3::Zero()).determinant();
  }
  return {{"energy_density", density}, {"volume_ratio", ratio}, {"energy_ratio", energy}};
}

}  // namespace sinew
