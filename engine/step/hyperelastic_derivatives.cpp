#include "engine/step/hyperelastic_derivatives.hpp"

#include "engine/assembly/hyperelastic_batches.hpp"
#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/assembly/node_elements.hpp"
#include "engine/assembly/scatter_stiffness.hpp"

namespace sinew {

void hyperelastic_derivatives(const Model& model, const VecX& x, bool exact, std::vector<double>& energy,
                              std::vector<double>& force2, VecX& gradient, double* values,
                              std::vector<Vec24>& element_gradients) {
  energy.assign(model.num_elements, 0.0);
  force2.assign(model.num_elements, 0.0);
  element_gradients.resize(model.num_elements);
  // g over the element's `count` nodes.
  const auto keep_gradient = [&](int e, int count, const auto& g) {
    force2[e] = g.squaredNorm();
    element_gradients[e].head(3 * count) = g.head(3 * count);
  };
  // given: F and its SVD, for a tet whose projected Hessian is wanted (from the batch below), or null.
  const auto visit = [&](int e, const ElementNodes& nodes, const ElementQuadrature& quad,
                         const GivenDeformation* given) {
    const Material& material = *model.bodies[model.element_body[e]].hyperelastic;
    // Tets: the exact Hessian (Newton near convergence) in 12 x 12 and scattered, the projected
    // one added straight into the values.
    if (nodes.count == 4 && !quad.mean_dilatation) {
      Vec12 g;
      if (values && exact) {
        Mat12 K;
        energy[e] = hyperelastic_tet_exact_derivatives(material, quad, nodes, g, K);
        scatter_element_matrix(model, e, K, model.h * model.h, values);
      } else if (values) {  // projected: added straight into the values (tet_hessian_scatter.hpp)
        const TetHessianScatter scatter{model.pattern.element_scatter.data() + model.pattern.scatter_begin[e],
                                        model.h * model.h, values};
        energy[e] = hyperelastic_tet_derivatives(material, quad, nodes, g, scatter, given);
      } else {
        energy[e] = hyperelastic_tet_derivatives(material, quad, nodes, g, nullptr, given);
      }
      keep_gradient(e, 4, g);
      return;
    }
    Vec24 g;
    Mat24 K;
    energy[e] = values && exact ? hyperelastic_element_exact_derivatives(material, quad, nodes, g, K)
                                : hyperelastic_element_derivatives(material, quad, nodes, g, values ? &K : nullptr);
    keep_gradient(e, nodes.count, g);
    if (values) scatter_element_matrix(model, e, K, model.h * model.h, values);
  };
  // The projected tet Hessians' SVDs four at a time (hyperelastic_batches.hpp).
  for_each_hyperelastic_element(model, x, values && !exact, visit, values != nullptr);
  // A free node's elements are all of its body, hyperelastic or not alike, and awake.
  gradient.resize(3 * model.num_free);
  const auto& entries = model.node_elements.entries;
  sum_by_node(model.node_elements, [&](int n, int first, int last) {
    const int f = model.free_index[n];
    if (f < 0) return;
    Vec3 sum = Vec3::Zero();
    if (first < last && is_hyperelastic_element(model, entries[first].first))
      for (int k = first; k < last; ++k) sum += element_gradients[entries[k].first].segment<3>(3 * entries[k].second);
    gradient.segment<3>(3 * f) = sum;
  });
}

}  // namespace sinew
