#include <tbb/parallel_for.h>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/step/stages.hpp"

namespace sinew {

// Backward Euler with Rayleigh damping D = alpha M + beta K (paper 000, eq. 19):
//   A = M - h dF/dv - h^2 dF/dx = (1 + h alpha) M + (h beta + h^2) K
//   b = (M - h dF/dv) v0 + h F(x0, v0) = M v0 + h (f_elastic(x0) + M g + f_ext)
// (the damping force in F cancels the h dF/dv v0 term). K is the warped stiffness
// R Ke R^T with R frozen over the step.
void assemble_system(const Model& model, State& state) {
  const double h = model.h;
  for (int n = 0; n < model.num_nodes; ++n)
    state.force.segment<3>(3 * n) =
        model.node_mass[n] * model.gravity + state.external_force.segment<3>(3 * n);
  // Scene loads at the end of the step (backward Euler evaluates forces there).
  for (const NodeLoad& load : model.loads) {
    const double ramp = load.ramp(state.t + h);
    for (int n : load.nodes) state.force.segment<3>(3 * n) += ramp * load.node_force;
  }

  // Rotations and elastic forces; a colour's elements share no node, so the force
  // scatter needs no lock and sums in a fixed order.
  std::vector<double>& k_scale = state.element_scratch;
  k_scale.resize(model.num_elements);
  for (const std::vector<int>& color : model.element_colors) {
    state.profile.work.elements += static_cast<long>(color.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, color.size(), 16), [&](const auto& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const int e = color[i];
        const Body& body = model.bodies[model.element_body[e]];
        // Hyperelastic elements enter through solve_newton. Their R serves only an energy
        // limit's curvature (R Ke R^T, solve_velocity); without a limit the polar
        // decomposition (an SVD per element) is skipped.
        if (body.hyperelastic && model.element_Umax[e] == 0) {
          k_scale[e] = 0;
          continue;
        }
        const ElementNodes nodes = gather_element_nodes(model, state.x, e);
        const CorotatedElement c = compute_corotated_element(model, e, nodes);
        state.R[e] = c.R;
        if (body.hyperelastic) {
          k_scale[e] = 0;
          continue;
        }
        const Vec24 f = element_elastic_force(model, e, c.R, c.u);
        for (int a = 0; a < nodes.count; ++a)
          state.force.segment<3>(3 * model.element_nodes[e][a]) += f.segment<3>(3 * a);
        k_scale[e] = h * body.damping_stiffness + h * h;
      }
    });
  }

  double* values = state.system.valuePtr();
  std::fill_n(values, state.system.nonZeros(), 0.0);
  scatter_warped_stiffness(model, state.R, k_scale, values);
  for (int n = 0; n < model.num_nodes; ++n) {
    const int fi = model.free_index[n];
    if (fi < 0) continue;
    const Body& body = model.bodies[model.node_body[n]];
    const double m = model.node_mass[n];
    for (int d = 0; d < 3; ++d) {
      values[model.pattern.diagonal[3 * fi + d]] += (1 + h * body.damping_mass) * m;
      state.rhs[3 * fi + d] = m * state.v[3 * n + d] + h * state.force[3 * n + d];
    }
  }
}

}  // namespace sinew
