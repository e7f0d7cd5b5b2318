#pragma once
// The stages of World::step(), one file each (docs/ARCHITECTURE.md lists them in order).
#include "engine/model.hpp"
#include "engine/solve/linear_solver.hpp"
#include "engine/state.hpp"

namespace sinew {

// 1. Element rotations, warped stiffness and forces at x0; the system A and right-hand
//    side b of backward Euler (paper 000, eq. 19) over free DOFs.
void assemble_system(const Model& model, State& state);

// 2-3. Factorise H = A + the constraints' curvature (state.curvature; H = A without
//      constraints) and take the Newton step v = v0 + H^-1 (b - A v0), which is v* = A^-1 b
//      when H = A; scattered into state.v (fixed nodes: 0). False if factorisation failed.
bool solve_velocity(const Model& model, LinearSolver& solver, State& state);
// The factorisation alone. H^-1 on the touched nodes (state.touched_inverse) is forgotten,
// or kept as an approximation while solver.delassus_reuse allows and `may_keep_delassus`.
bool factorize_step_system(const Model& model, LinearSolver& solver, State& state, bool may_keep_delassus = true);
// state.curvature and curvature_blocks from the rows solve_constraints left pending
// (state.curvature_pending); a no-op when none are. factorize_step_system calls it first.
void settle_curvature(const Model& model, State& state);

// 2-3 for scenes with hyperelastic bodies (paper 003): Newton on the incremental potential
//    from the previous velocities; leaves system/rhs as the quadratic model at the result.
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
