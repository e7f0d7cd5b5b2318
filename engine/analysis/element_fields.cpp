#include "engine/analysis/element_fields.hpp"

#include <Eigen/LU>
#include <cmath>

#include "engine/assembly/element_kernels.hpp"

namespace sinew {

Vec24 element_corotated_displacement(const Model& model, const VecX& x, int e, Mat3* rotation) {
  const CorotatedElement c = compute_corotated_element(model, e, gather_element_nodes(model, x, e));
  if (rotation) *rotation = c.R;
  return c.u;
}

std::map<std::string, std::vector<double>> compute_element_fields(const Model& model, const State& state) {
  std::vector<double> density(model.num_elements), ratio(model.num_elements), energy(model.num_elements);
  for (int e = 0; e < model.num_elements; ++e) {
    const ElementNodes nodes = gather_element_nodes(model, state.x, e);
    const Vec24 u = compute_corotated_element(model, e, nodes).u;
    const double Ue = element_limit_energy(model, e, u);
    density[e] = 0.5 * Ue / element_rest_volume(model, e);
    energy[e] = model.element_Umax[e] > 0 ? Ue / model.element_Umax[e] : 0.0;
    ratio[e] = element_center_deformation_gradient(model, e, nodes).determinant();
  }
  return {{"energy_density", density}, {"volume_ratio", ratio}, {"energy_ratio", energy}};
}

}  // namespace sinew
