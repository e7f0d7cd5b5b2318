#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/step/stages.hpp"

namespace sinew {
namespace {

// Positions x0 + h v (fixed nodes stay at x0) from free velocities.
void positions_at(const Model& model, const VecX& x0, const VecX& v_free, VecX& x) {
  x = x0;
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0) x.segment<3>(3 * n) += model.h * v_free.segment<3>(3 * f);
}

void gather_free(const Model& model, const VecX& full, VecX& free) {
  free.resize(3 * model.num_free);
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0) free.segment<3>(3 * f) = full.segment<3>(3 * n);
}

bool is_hyperelastic(const Model& model, int e) {
  return model.bodies[model.element_body[e]].hyperelastic != nullptr;
}

// Sum of the hyperelastic elements' energies at x (+infinity if any is undefined).
double hyperelastic_energy(const Model& model, const VecX& x) {
  std::vector<double> energy(model.num_elements, 0.0);
  tbb::parallel_for(0, model.num_elements, [&](int e) {
    if (!is_hyperelastic(model, e)) return;
    energy[e] = hyperelastic_element_energy(*model.bodies[model.element_body[e]].hyperelastic,
                                            element_quadrature(model, e), gather_element_nodes(model, x, e));
  });
  double sum = 0;
  for (double v : energy) sum += v;  // fixed order: the same sum for any thread count
  return sum;
}

// Gradient over free DOFs (dPsi/dx, free nodes only) and, if `values` is not null,
// h^2 times the projected Hessians scattered into a matrix of the system pattern.
void hyperelastic_derivatives(const Model& model, const VecX& x, VecX& gradient, double* values) {
  gradient.setZero(3 * model.num_free);
  for (const std::vector<int>& color : model.element_colors) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, color.size(), 16), [&](const auto& range) {
      Vec24 g;
      Mat24 K;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const int e = color[i];
        if (!is_hyperelastic(model, e)) continue;
        const ElementNodes nodes = gather_element_nodes(model, x, e);
        hyperelastic_element_derivatives(*model.bodies[model.element_body[e]].hyperelastic,
                                         element_quadrature(model, e), nodes, g, values ? &K : nullptr);
        for (int a = 0; a < nodes.count; ++a)
          if (const int f = model.free_index[model.element_nodes[e][a]]; f >= 0)
            gradient.segment<3>(3 * f) += g.segment<3>(3 * a);
        if (values) scatter_element_matrix(model, e, K, model.h * model.h, values);
      }
    });
  }
}

}  // namespace

// Backward Euler for hyperelastic bodies as the minimisation of the incremental potential
// (paper 003, sec. 6), in velocities v over free DOFs, x = x0 + h v:
//   Phi(v) = 1/2 v^T A0 v - b0^T v + Psi(x0 + h v)
// A0, b0 (assemble_system) hold mass, mass damping, gravity, applied loads and the linear
// corotational bodies; Psi sums the hyperelastic elements. Then
//   grad Phi = A0 v - b0 + h dPsi/dx,   Hess Phi ~= A0 + h^2 (projected d2Psi/dx2).
// Newton with backtracking (Armijo) line search, from the previous step's velocities, until
// |grad Phi| <= newton_tolerance max(|grad Phi(v0)|, |b0|, h |dPsi/dx(x0 + h v0)|) or the
// iteration cap. On exit the system
// and rhs describe the quadratic model around the result, so solve_constraints treats it
// like the linear path's v*: state.system = the last Hessian (factorised), rhs = H v - grad.
bool solve_newton(const Model& model, LinearSolver& solver, State& state) {
  const SolverDesc& cfg = model.solver;
  const VecX x0 = state.x;
  const SparseMatrix A0 = state.system;
  const VecX b0 = state.rhs;
  VecX v, x, dPsi, gradient, direction;
  gather_free(model, state.v, v);

  auto potential = [&](const VecX& vv) {
    positions_at(model, x0, vv, x);
    return 0.5 * vv.dot(A0 * vv) - b0.dot(vv) + hyperelastic_energy(model, x);
  };
  int newton = 0, linear = 0;
  double first_norm = -1;
  bool ok = true, factorised = false;
  SparseMatrix H = A0;
  auto factorize = [&] {
    StageTimer timer(state.profile, Stage::Factorize);
    state.system = H;
    factorised = factorize_step_system(model, solver, state);
    state.factor_exact = !state.factor_curved;
    return factorised;
  };
  for (;; ++newton) {
    positions_at(model, x0, v, x);
    {
      StageTimer timer(state.profile, Stage::Assemble);
      H = A0;
      hyperelastic_derivatives(model, x, dPsi, H.valuePtr());
    }
    gradient = A0 * v - b0 + model.h * dPsi;
    const double norm = gradient.norm();
    if (!std::isfinite(norm)) {
      ok = false;
      break;
    }
    // Scale of the residual: the larger of the first gradient and the step's momentum and
    // forces, so that a warm start already near the solution is not asked for a tiny
    // fraction of an already tiny residual (round-off would stop it first).
    if (first_norm < 0) first_norm = std::max({norm, b0.norm(), model.h * dPsi.norm()});
    // Converged: the factorisation of the last iterate's Hessian stays (one is made if the
    // start was already converged, for solve_constraints).
    state.profile.violation["newton_residual"] = first_norm > 0 ? norm / first_norm : 0.0;
    if (norm <= cfg.newton_tolerance * first_norm || norm == 0 || newton == cfg.newton_max_iterations) {
      if (!factorised) ok = factorize();
      break;
    }
    if (!factorize()) {
      ok = false;
      break;
    }
    StageTimer timer(state.profile, Stage::Solve);
    direction = VecX::Zero(v.size());
    linear += solver.solve(-gradient, direction);
    // Backtracking: halve until Phi decreases enough (Armijo, c = 1e-4); an undefined energy
    // (inverted neo_hookean element) is +infinity and so always rejected.
    const double phi0 = potential(v), slope = gradient.dot(direction);
    double alpha = 1;
    for (int k = 0; k < 20 && !(potential(v + alpha * direction) <= phi0 + 1e-4 * alpha * slope); ++k) alpha *= 0.5;
    v += alpha * direction;
  }
  // The quadratic model around v that solve_constraints continues from.
  if (ok) {
    state.rhs = state.system * v - gradient;
    state.v_free = v;
    for (int n = 0; n < model.num_nodes; ++n) {
      const int f = model.free_index[n];
      state.v.segment<3>(3 * n) = f >= 0 ? Vec3(v.segment<3>(3 * f)) : Vec3::Zero();
    }
  }
  state.profile.iterations["newton"] += newton;
  if (!solver.uses_cholmod()) state.profile.iterations["pcg"] += linear;
  return ok;
}

}  // namespace sinew
