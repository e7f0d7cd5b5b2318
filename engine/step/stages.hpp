#pragma once
// The stages of World::step(), one file each (docs/ARCHITECTURE.md lists them in order).
#include <algorithm>

#include "engine/model.hpp"
#include "engine/solve/linear_solver.hpp"
#include "engine/state.hpp"

namespace sinew {

// 1. Element rotations, warped stiffness weights and forces at x0; the right-hand side b of
//    backward Euler (paper 000, eq. 19) over free DOFs, and its system A into state.system
//    only where the step certainly needs the matrix (hyperelastic bodies, PCG): with
//    CHOLMOD, a step that reuses an earlier factorisation only multiplies by A, which
//    multiply_step_system does element by element.
void assemble_system(const Model& model, State& state);
// A into state.system, unless this step's is there already (state.system_assembled): before
// a factorisation, or for a caller that reads the matrix. With no linear element awake in a
// hyperelastic scene, its diagonal alone (the mass): the other values are left stale, and
// solve_newton, A's one reader there, takes the diagonal (until it swaps its H in).
void assemble_system_matrix(const Model& model, State& state);
// Whether A is the mass diagonal alone this step: no element with stiffness awake (every
// stiffness_scale 0, as assemble_system leaves them). Both assemble_system_matrix and
// solve_newton decide by it.
inline bool system_is_mass_diagonal(const State& state) {
  return std::all_of(state.stiffness_scale.begin(), state.stiffness_scale.end(), [](double s) { return s == 0; });
}
// out = A x over the free DOFs: the assembled matrix when there is one, else the mass
// diagonal plus sum_e s_e R_e Ke_e R_e^T x_e (s_e = state.stiffness_scale), the same terms
// summed in another order; the same for any thread count.
void multiply_step_system(const Model& model, const State& state, const VecX& x, VecX& out);
// out1 = A x1 and out2 = A x2 in one pass over the elements (each as the one above computes it).
void multiply_step_system(const Model& model, const State& state, const VecX& x1, VecX& out1, const VecX& x2,
                          VecX& out2);

// 2-3. Factorise H = A + the constraints' curvature (state.curvature; H = A without
//      constraints) and take the Newton step v = v0 + H^-1 (b - A v0), which is v* = A^-1 b
//      when H = A; scattered into state.v (fixed nodes: 0). False if factorisation failed.
bool solve_velocity(const Model& model, LinearSolver& solver, State& state);
// Whether the next solve_velocity keeps the factorisation it holds by refactor_interval or
// curved_refactor_interval (solve_velocity decides by this; it may also keep one whose
// rotations did not move, which only the step's assembly can tell). `uses_cholmod`: PCG
// never keeps one. For the real-time budget's forecast of the next step's cost.
bool reuses_factorisation(const Model& model, bool uses_cholmod, const State& state);
// A due factorisation replaced by the one the solver holds, which is this step's (the same
// matrix): as a factorisation made now, with what was solved with it kept; stats:
// `factorize` skipped with `reason`.
void keep_factorisation_as_current(const Model& model, State& state, const char* reason);
// The factorisation alone. H^-1 on the touched nodes (state.touched_inverse) is forgotten,
// or kept as an approximation while solver.delassus_reuse allows and `may_keep_delassus`.
bool factorize_step_system(const Model& model, LinearSolver& solver, State& state, bool may_keep_delassus = true);
// state.curvature and curvature_blocks from the rows solve_constraints left pending
// (state.curvature_pending); a no-op when none are. factorize_step_system calls it first.
void settle_curvature(const Model& model, State& state);
// Whether the settled curvature adds anything to A.
bool has_curvature(const State& state);
// How the step's solves use the factorisation the solver holds (solver.stale_factor_precision):
// exactly when it is this step's A (factor_exact), a reused one of the same A (no rotation
// moved: factor_unmoved; its single-precision round-off would strain a body at rest, turn
// its rotations and cost the factorisation the next due step skips), or one with the
// constraints' curvature (with single-precision solves the settled side-pressed finger's QP
// steps took 13 line-search halvings in 21 steps instead of none,
// tests/engine/step/test_curved_factor_reuse.cpp); else as a preconditioner, an earlier
// step's factorisation of another A.
inline LinearSolver::FactorUse factor_use(const State& state) {
  return state.factor_exact || state.factor_unmoved || state.factor_curved ? LinearSolver::FactorUse::Exact
                                                                            : LinearSolver::FactorUse::Preconditioner;
}

// 2-3 for scenes with hyperelastic bodies (paper 003): Newton on the incremental potential
//    from the previous velocities; leaves system and model_residual (rhs - system v) as the
//    quadratic model at the result.
//    With refactor_interval > 1, between factorisations each direction comes from CG on
//    the current Hessian preconditioned with the last factorisation, stopped unconverged
//    after kNewtonPcgCap iterations or at a direction without positive curvature (H is
//    then factorised; stats: newton_pcg_fallbacks). A step whose CG on the projected
//    Hessian stopped so marks the factorisation spent (state.newton_factor_spent): the next
//    step factorises at its first Newton iteration and preconditions its later ones with
//    that factorisation.
constexpr int kNewtonPcgCap = 12;
bool solve_newton(const Model& model, LinearSolver& solver, State& state);

// 4. Constraints (paper 000, section 5): rows at x* = x0 + h v*, the LCP of eq. 23 by
//    projected Gauss-Seidel, and SQP re-linearisation at the corrected positions until
//    the worst violation meets the tolerance. Updates state.v.
void solve_constraints(const Model& model, LinearSolver& solver, State& state);

// 5. x = x0 + h v.
void integrate_positions(const Model& model, State& state);

// 6. Embedded surfaces from the lattice.
void update_surfaces(const Model& model, State& state);

}  // namespace sinew
