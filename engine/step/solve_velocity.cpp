#include <algorithm>

#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/step/stages.hpp"

namespace sinew {

namespace {

// Factorises `matrix`; on success records the rotations it was assembled with (A's only
// dependence on the positions), so that a later step may keep it (solve_velocity).
bool factorize_recording(LinearSolver& solver, State& state, const SparseMatrix& matrix) {
  state.factor_rotations.clear();  // a failed factorisation is never kept
  if (!solver.factorize(matrix)) return false;
  state.factor_rotations = state.R;  // same size every time: no allocation once warm
  return true;
}

// Whether H^-1 kept on the touched nodes (solver.delassus_reuse) may serve one more
// factorisation: it is counted from the step that first filled it, and is dropped once it
// holds more than twice the nodes of that first fill (contacts that slide or roll onto new
// nodes would otherwise grow G, dense in its nodes, and every build of W from it, over the
// whole reuse window while most of its nodes no longer carry a row).
bool touched_inverse_young(const Model& model, const State& state) {
  return state.step_count - state.touched_inverse_step < model.solver.delassus_reuse &&
         state.touched_inverse.size() <= 2 * std::max(1, state.touched_inverse_first_nodes);
}

// Rotations this close to the factorisation's leave A equal to the factored matrix up to
// round-off: R comes from position differences, whose round-off at 10 m from the origin in
// 0.1 m cells is ~1e-14; the margin of 100 keeps A within ~1e-12 of the factored one.
constexpr double kUnmovedRotation = 1e-12;

// Whether the factorisation still holds this step's A: A = (1 + h alpha) M + sum_e s_e R_e
// Ke R_e^T changes only with the rotations (the mass, the weights s_e and the pattern only with
// h or the sleeping set, whose changes clear factor_rotations), so a body that only translates
// (a fall before it lands) or lies still keeps it. Not when curvature was factored or is due.
// Whether no rotation moved since an uncurved factorisation (the first half of the test below).
bool factor_rotations_unmoved(const Model& model, const State& state) {
  if (state.factor_curved || state.factor_rotations.size() != state.R.size()) return false;
  for (int e = 0; e < model.num_elements; ++e)
    if (state.stiffness_scale[e] != 0 &&
        (state.R[e] - state.factor_rotations[e]).cwiseAbs().maxCoeff() > kUnmovedRotation)
      return false;
  return true;
}

bool factorisation_still_current(const Model& model, const LinearSolver& solver, State& state) {
  if (!solver.uses_cholmod() || !factor_rotations_unmoved(model, state)) return false;
  settle_curvature(model, state);  // a no-op unless rows are pending; a factorisation would do it first
  return !has_curvature(state);
}

}  // namespace

// Whether the settled curvature adds anything to A.
bool has_curvature(const State& state) {
  return !state.curvature_blocks.empty() ||
         std::any_of(state.curvature.begin(), state.curvature.end(), [](double c) { return c != 0; });
}

void keep_factorisation_as_current(const Model& model, State& state, const char* reason) {
  // With what was solved with it: H^-1's columns on the touched nodes and the rows' columns
  // are still exact. A G kept from an earlier factorisation (delassus_reuse) ages as it
  // would have at a factorisation.
  state.factor_age = 0;
  state.factor_exact = true;
  if (state.touched_inverse.stale() && !touched_inverse_young(model, state)) state.touched_inverse.reset(model.num_free);
  state.profile.skipped[static_cast<int>(Stage::Factorize)] = reason;
}

// Factorises H = A + (the constraints' curvature from the previous step, if any) and takes
// one Newton step from the previous velocities: v = v0 + H^-1 (b - A v0). Without
// constraints H = A and this is v* = A^-1 b of eq. 19; with them, the same factorisation
// serves every SQP iteration of the step (solve_constraints), so a step that keeps its
// contacts and limits costs one factorisation, not one per iteration.
bool factorize_step_system(const Model& model, LinearSolver& solver, State& state, bool may_keep_delassus) {
  assemble_system_matrix(model, state);
  settle_curvature(model, state);
  state.factor_age = 0;
  // Kept G: columns of an earlier H, corrected for in solve_constraints. Only with CHOLMOD,
  // whose columns are exact for the H they came from; for delassus_reuse steps from the
  // first step that filled it. The per-row columns are exact by contract: always dropped.
  const bool keep = may_keep_delassus && solver.uses_cholmod() && state.touched_inverse.size() > 0 &&
                    touched_inverse_young(model, state);
  if (keep) state.touched_inverse.keep_stale();
  else state.touched_inverse.reset(model.num_free);
  state.row_columns.reset();
  state.factor_curved = has_curvature(state);
  if (state.factor_curved) {
    state.sqp_system = state.system;
    scatter_warped_stiffness(model, state.R, state.curvature, state.sqp_system.valuePtr());
    Mat24 K = Mat24::Zero();
    for (const auto& [e, block] : state.curvature_blocks) {
      K.topLeftCorner<12, 12>() = block;
      scatter_element_matrix(model, e, K, 1.0, state.sqp_system.valuePtr());
    }
  }
  if (!state.factor_curved) return factorize_recording(solver, state, state.system);
  if (factorize_recording(solver, state, state.sqp_system)) return true;
  // A + curvature is PSD-plus-PD in exact arithmetic, but curvature blocks many orders above
  // A (large multipliers on nearly repeated singular values) can lose a pivot to round-off:
  // fall back to H = A, which SQP tolerates (it only converges more slowly), and say so.
  ++state.profile.iterations["curvature_dropped"];
  state.factor_curved = false;
  state.curvature.clear();
  state.curvature_blocks.clear();
  return factorize_recording(solver, state, state.system);
}

bool reuses_factorisation(const Model& model, bool uses_cholmod, const State& state) {
  const int age = state.factor_age + 1;  // at the next step
  return uses_cholmod && state.step_count > 0 &&
         (age < model.solver.refactor_interval ||
          (state.factor_curved && state.keep_curved_factor && !state.factor_rotations.empty() &&
           age < model.solver.curved_refactor_interval));
}

bool solve_velocity(const Model& model, LinearSolver& solver, State& state) {
  solver.keep_factored_matrix(false);  // Newton's test (holds_factor_of) alone needs the copy
  {
    StageTimer timer(state.profile, Stage::Factorize);
    // PCG never reuses: its "factorisation" is the diagonal and a pointer to the matrix its
    // solves use, which must be this step's (a reused one could be an older step's matrix
    // with constraint curvature in it).
    // A curved factorisation (the constraints' curvature in H) is not the step's A either
    // way: the SQP iterations converge from it as from a fresh one, and keeping it while
    // they take no more iterations than the step that made it saves a factorisation and
    // its curvature blocks (strain rows: 10 constraint evaluations per tet).
    const bool reuse = reuses_factorisation(model, solver.uses_cholmod(), state);
    ++state.factor_age;
    state.factor_unmoved = false;
    if (!reuse && state.step_count > 0 && factorisation_still_current(model, solver, state)) {
      keep_factorisation_as_current(model, state, "no rotation moved since the last factorisation");
    } else if (reuse) {
      state.factor_exact = false;
      // Still this step's A when no rotation moved (a fall, a body at rest): factor_use.
      state.factor_unmoved = solver.uses_cholmod() && factor_rotations_unmoved(model, state);
      // A G kept from before this factorisation (delassus_reuse) ages as at a factorisation.
      if (state.touched_inverse.stale() && !touched_inverse_young(model, state)) state.touched_inverse.reset(model.num_free);
      // PCG keeps no factor: its solves use this step's matrix, so columns of H^-1 solved
      // in an earlier step are stale.
      if (!solver.uses_cholmod()) {
        state.touched_inverse.reset(model.num_free);
        state.row_columns.reset();
      }
      state.profile.skipped[static_cast<int>(Stage::Factorize)] = "reusing the factorisation of an earlier step";
    } else {
      if (!factorize_step_system(model, solver, state)) return false;
      state.factor_exact = !state.factor_curved;
    }
  }
  StageTimer timer(state.profile, Stage::Solve);
  VecX& v0 = state.v_start;  // the start-of-step velocities on the free DOFs
  v0.resize(3 * model.num_free);
  for (int n = 0; n < model.num_nodes; ++n) {
    const int fi = model.free_index[n];
    if (fi >= 0) v0.segment<3>(3 * fi) = state.v.segment<3>(3 * n);
  }
  const VecX& residual = state.start_residual;  // b - A v0, from assemble_system's element pass
  VecX& delta = state.scratch.step;
  delta.setZero(v0.size());
  // With an earlier step's factorisation of another A, v_free is the SQP's first guess, not A^-1 b.
  solver.solve(residual, delta, factor_use(state));  // PCG's counts: World::attempt_step
  state.v_free = v0 + delta;
  for (int n = 0; n < model.num_nodes; ++n) {
    const int fi = model.free_index[n];
    state.v.segment<3>(3 * n) = fi >= 0 ? Vec3(state.v_free.segment<3>(3 * fi)) : Vec3::Zero();
  }
  return true;
}

}  // namespace sinew
