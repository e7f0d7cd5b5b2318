#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <stdexcept>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/for_each_scheduled_element.hpp"
#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/solve/system_product.hpp"
#include "engine/step/stages.hpp"

namespace sinew {

namespace {

// The sums by node over the model's incidence (node_elements.hpp).
template <typename Sum>
void sum_by_node(const Model& model, const Sum& sum) {
  sinew::sum_by_node(model.node_elements, sum);
}

// Whether assemble_system must leave the matrix: solve_newton starts from it, and PCG
// multiplies by it at every iteration.
bool matrix_needed(const Model& model) { return model.has_hyperelastic || model.solver.linear == "pcg"; }

double mass_coefficient(const Model& model, int node) {
  return (1 + model.h * model.bodies[model.node_body[node]].damping_mass) * model.node_mass[node];
}

// out += sign * column `column` of each element's 24-row block, on the free DOFs of its
// nodes, by node in element order (sum_by_node). Elements of scale 0 carry no stiffness this
// step, and their blocks are not read.
template <typename Block>
void add_element_blocks(const Model& model, const std::vector<double>& scale, const std::vector<Block>& blocks,
                        int column, double sign, VecX& out) {
  sum_by_node(model, [&](int n, int first, int last) {
    const int f = model.free_index[n];
    if (f < 0) return;
    for (int k = first; k < last; ++k)
      if (const auto [e, a] = model.node_elements.entries[k]; scale[e] != 0)
        out.segment<3>(3 * f) += sign * blocks[e].template block<3, 1>(3 * a, column);
  });
}

}  // namespace

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

  // Rotations and elastic forces of all elements in one parallel loop, then summed into the
  // force by node (sum_by_node: each node's terms in element order, the same sums for any
  // thread count). Colour by colour with the sums in the tasks, as before, cost 8
  // fork-joins. The same loop applies each element's stiffness to the start-of-step velocities, K (R^T v0) beside K u, for
  // stage 3's residual b - A v0 (one product with A fewer per step).
  std::vector<double>& scale = state.stiffness_scale;
  scale.resize(model.num_elements);
  // Kept storage (a warm step allocates nothing), bound to local references for the tasks.
  thread_local std::vector<Vec24> forces_storage, products_storage;
  std::vector<Vec24>& forces = forces_storage;
  std::vector<Vec24>& products = products_storage;  // s_e R Ke R^T v0_e
  forces.resize(model.num_elements);
  const bool residual = !model.has_hyperelastic;  // stage 3' (solve_newton) has its own
  if (residual) products.resize(model.num_elements);
  for (const std::vector<int>& color : model.element_colors)  // a sleeping body's elements are in none
    state.profile.work.elements += static_cast<long>(color.size());
  // Whether any element carries stiffness this step: with none (every awake body
  // hyperelastic), the sums by node below would add nothing, and b alone is formed.
  std::atomic<bool> any_stiffness{false};
  tbb::parallel_for(tbb::blocked_range<int>(0, model.num_elements, 8), [&](const tbb::blocked_range<int>& range) {
    bool stiffness = false;
    for (int e = range.begin(); e != range.end(); ++e) {
      const Body& body = model.bodies[model.element_body[e]];
      scale[e] = 0;
      if (model.asleep(model.element_body[e])) continue;  // its nodes are not unknowns: left as they are
      // Hyperelastic elements enter through solve_newton. Their R serves only an energy
      // limit's curvature (R Ke R^T, solve_velocity); without a limit the polar
      // decomposition (an SVD per element) is skipped.
      if (body.hyperelastic && model.element_Umax[e] == 0) continue;
      const ElementNodes nodes = gather_element_nodes(model, state.x, e);
      const CorotatedElement c = compute_corotated_element(model, e, nodes);
      state.R[e] = c.R;
      if (body.hyperelastic) continue;
      scale[e] = h * body.damping_stiffness + h * h;
      stiffness = true;
      if (!residual) {
        forces[e] = element_elastic_force(model, e, c.R, c.u);
        continue;
      }
      // Ke [u, R^T v0_e] in one product (v0 on free nodes; a fixed node's is not an unknown).
      Eigen::Matrix<double, 24, 2> local = Eigen::Matrix<double, 24, 2>::Zero();
      local.col(0) = c.u;
      for (int a = 0; a < nodes.count; ++a)
        if (model.free_index[model.element_nodes[e][a]] >= 0)
          local.block<3, 1>(3 * a, 1).noalias() = c.R.transpose() * state.v.segment<3>(3 * model.element_nodes[e][a]);
      const Eigen::Matrix<double, 24, 2> stiff = element_stiffness_times(model, e, local);
      for (int a = 0; a < nodes.count; ++a) {
        forces[e].segment<3>(3 * a).noalias() = -(c.R * stiff.block<3, 1>(3 * a, 0));
        products[e].segment<3>(3 * a).noalias() = scale[e] * (c.R * stiff.block<3, 1>(3 * a, 1));
      }
    }
    if (stiffness) any_stiffness.store(true, std::memory_order_relaxed);
  });
  // Per node, in parallel: its elements' forces, then b, then b - A v0 = b - (mass
  // diagonal) v0 - sum_e s_e R Ke R^T v0_e.
  VecX& r = state.start_residual;
  if (residual) r.resize(3 * model.num_free);
  const auto& entries = model.node_elements.entries;
  const auto form_rhs = [&](int n, int fi) {
    for (int d = 0; d < 3; ++d) state.rhs[3 * fi + d] = model.node_mass[n] * state.v[3 * n + d] + h * state.force[3 * n + d];
  };
  if (!any_stiffness.load() && !residual) {
    // No element force to add (cube_20: the 52,800 incidences' pass skipped): b alone.
    for (int n = 0; n < model.num_nodes; ++n)
      if (const int fi = model.free_index[n]; fi >= 0) form_rhs(n, fi);
  } else {
    sum_by_node(model, [&](int n, int first, int last) {
      for (int k = first; k < last; ++k)
        if (const auto [e, a] = entries[k]; scale[e] != 0) state.force.segment<3>(3 * n) += forces[e].segment<3>(3 * a);
      const int fi = model.free_index[n];
      if (fi < 0) return;
      form_rhs(n, fi);
      if (!residual) return;
      r.segment<3>(3 * fi) = state.rhs.segment<3>(3 * fi) - mass_coefficient(model, n) * state.v.segment<3>(3 * n);
      for (int k = first; k < last; ++k)
        if (const auto [e, a] = entries[k]; scale[e] != 0) r.segment<3>(3 * fi) -= products[e].segment<3>(3 * a);
    });
  }
  state.system_assembled = false;
  if (matrix_needed(model)) assemble_system_matrix(model, state);
}

// Each element's R Ke R^T formed and scattered at once, through the element schedule
// (for_each_scheduled_element: a colour's blocks of consecutive elements in parallel, no two
// sharing a node; each entry takes its terms in (colour, element) order, the same for any
// thread count). The matrix stays in cache between the two, and the scatter, bound by
// memory, runs on both threads. Before, the elements' matrices were formed in parallel into
// a buffer and scattered by one thread in element order; 2 threads, median of 15 calls
// (sinew_scale_sweep's block): 2,662 hex 2.33 -> 1.57 ms, 9,826 hex 9.4 -> 6.3 ms, 21,296
// hex 24.6 -> 14.7 ms. Scattering by node instead (each node's columns, sum_by_node) read
// the element matrices scattered and was slower.
void assemble_system_matrix(const Model& model, State& state) {
  if (state.system_assembled) return;
  const std::vector<double>& scale = state.stiffness_scale;
  if (static_cast<int>(scale.size()) != model.num_elements)
    throw std::logic_error("assemble_system_matrix: assemble_system has not run on this model");
  double* values = state.system.valuePtr();
  const bool stiff = !system_is_mass_diagonal(state);
  // No element with stiffness this step (every awake body hyperelastic): A is the mass
  // diagonal, and the schedule's colours would be fork-joins over nothing (21 on bunny_5).
  // Its one reader then, solve_newton, takes that diagonal alone (A0_is_diagonal), so the
  // other values are left as they are, stale, not zeroed: a pass over 10 MB a step on cube_20
  // (2.7 M instructions). The diagonal is written, 0 + m's bits.
  const bool diagonal_only = !stiff && model.has_hyperelastic;
  if (!diagonal_only) std::fill_n(values, state.system.nonZeros(), 0.0);
  if (stiff)
    for_each_scheduled_element(model.element_schedule, [&](int e) {
      if (scale[e] == 0) return;
      Mat24 K;
      element_warped_stiffness(model, e, state.R[e], K);
      scatter_element_matrix(model, e, K, scale[e], values);
    });
  for (int n = 0; n < model.num_nodes; ++n) {
    const int fi = model.free_index[n];
    if (fi < 0) continue;
    for (int d = 0; d < 3; ++d) {
      double& value = values[model.pattern.diagonal[3 * fi + d]];
      value = (diagonal_only ? 0.0 : value) + mass_coefficient(model, n);
    }
  }
  state.system_assembled = true;
}

namespace {

// out_j = A x_j for the columns of X (1 or 2), element by element: per element
// s_e R (Ke (R^T x_e)), 8 rotations each way and one product with Ke (both columns at once),
// a fifth of forming R Ke R^T; summed by node in element order (add_element_blocks).
template <int Columns>
void multiply_elementwise(const Model& model, const State& state, const std::array<const VecX*, Columns>& x,
                          const std::array<VecX*, Columns>& out) {
  using Block = Eigen::Matrix<double, 24, Columns>;
  const std::vector<double>& scale = state.stiffness_scale;
  thread_local std::vector<Block> products_storage;  // kept storage, as in assemble_system
  std::vector<Block>& products = products_storage;
  products.resize(model.num_elements);
  tbb::parallel_for(tbb::blocked_range<int>(0, model.num_elements, 16), [&](const tbb::blocked_range<int>& range) {
    for (int e = range.begin(); e != range.end(); ++e) {
      if (scale[e] == 0) continue;
      const Mat3& R = state.R[e];
      const int count = element_node_count(model, e);
      Block local = Block::Zero();
      for (int a = 0; a < count; ++a)
        if (const int f = model.free_index[model.element_nodes[e][a]]; f >= 0)
          for (int j = 0; j < Columns; ++j) local.template block<3, 1>(3 * a, j).noalias() = R.transpose() * x[j]->template segment<3>(3 * f);
      Block stiff;
      if constexpr (Columns == 1) stiff = element_stiffness_times(model, e, Vec24(local));
      else stiff = element_stiffness_times(model, e, local);
      for (int a = 0; a < count; ++a)
        products[e].template middleRows<3>(3 * a).noalias() = scale[e] * (R * stiff.template middleRows<3>(3 * a));
    }
  });
  for (int j = 0; j < Columns; ++j) {
    VecX& o = *out[j];
    const VecX& in = *x[j];
    o.resize(in.size());
    for (int n = 0; n < model.num_nodes; ++n)
      if (const int fi = model.free_index[n]; fi >= 0) o.segment<3>(3 * fi) = mass_coefficient(model, n) * in.segment<3>(3 * fi);
    add_element_blocks(model, scale, products, j, 1.0, o);
  }
}

}  // namespace

void multiply_step_system(const Model& model, const State& state, const VecX& x, VecX& out) {
  if (state.system_assembled) {
    multiply_node_blocked(state.system, x, out);
    return;
  }
  multiply_elementwise<1>(model, state, {&x}, {&out});
}

void multiply_step_system(const Model& model, const State& state, const VecX& x1, VecX& out1, const VecX& x2,
                          VecX& out2) {
  if (state.system_assembled) {
    multiply_node_blocked(state.system, x1, out1);
    multiply_node_blocked(state.system, x2, out2);
    return;
  }
  multiply_elementwise<2>(model, state, {&x1, &x2}, {&out1, &out2});
}

}  // namespace sinew
