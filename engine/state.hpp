#pragma once
// The mutable part of a simulation: what every step changes. Each field says its shape
// and the stage that writes it.
#include <vector>

#include "engine/assembly/kept_tet_hessians.hpp"
#include "engine/assembly/system_pattern.hpp"
#include "engine/collision/body_surfaces.hpp"
#include "engine/constraints/attachment_rows.hpp"
#include "engine/constraints/row_table.hpp"
#include "engine/constraints/delassus.hpp"
#include "engine/constraints/lcp_active_set.hpp"
#include "engine/constraints/row_column_cache.hpp"
#include "engine/constraints/energy_screen.hpp"
#include "engine/constraints/touched_inverse.hpp"
#include "engine/core/kept_storage.hpp"
#include "engine/core/scratch_matrix.hpp"
#include "engine/core/types.hpp"
#include "engine/profile.hpp"
#include "engine/sleep/sleep_state.hpp"

namespace sinew {

// Vectors of the step (World, solve_velocity, solve_newton, solve_constraints), kept across
// steps so that a warm step allocates nothing: the VecX are 3 x free nodes or 3 x nodes,
// sizes that do not change.
// The row builders' buffers (engine/constraints/*.cpp).
struct EnergyRowBuffers;
struct StrainRowBuffers;
struct ContactRowBuffers;
struct BodyContactRowBuffers;

struct StepScratch {
  VecX step_x0, step_v0, attempt_x0, attempt_v0;  // World: states to roll back to
  VecX x_iterate, v_free, v_base, v_next, dv, residual, step, correction, impulse;
  VecX sqp_from, sqp_direction, sqp_feasible, sqp_product;  // SQP line search: v_k, its step, the last
                                                            // iterate within tolerance, A v
  VecX sqp_previous_direction, sqp_previous_product;  // the last search direction p and A p (conjugate steps)
  std::vector<std::pair<uint64_t, int>> kkt_rows;  // sqp_kkt_stop.hpp: the last QP's (key, row)
  std::vector<double> kkt_lambda;                  // and its multipliers on the new rows
  ScratchMatrix per_row;  // m x 6: the LCP's c, J (v_base - v_k), PGS's residual weights, W lambda_0,
                          // W~ lambda_0 and lambda_0 (solve_constraints)
  std::vector<uint64_t> keep;
  RowTable contact_rows;  // build_rows: contacts, built beside the limits' rows and appended to them
  std::vector<double> strain_cut_gaps;  // per element, the step's pair-cut gate (strain_pair_cut_gaps)
  // The row builders' buffers (kept_storage.hpp): theirs, not thread_local, as build_rows
  // runs them as tasks on whichever thread is free.
  KeptStorage<EnergyRowBuffers> energy_row_buffers;
  KeptStorage<StrainRowBuffers> strain_row_buffers;
  KeptStorage<ContactRowBuffers> contact_row_buffers;
  KeptStorage<BodyContactRowBuffers> body_contact_row_buffers;
  // solve_newton's
  SparseMatrix newton_A0, newton_H;
  VecX newton_A0_diagonal;  // A0's diagonal, when that is all of A0 (solve_newton)
  VecX newton_x0, newton_b0, newton_predicted_impulse, newton_v, newton_x, dPsi, gradient, quadratic_gradient, direction, trial, A0_direction,
      negative_gradient, dPsi_trial;
  std::vector<double> psi, psi_trial, force2, force2_trial;
  std::vector<Vec3> node_gradients;  // hyperelastic_derivatives' element gradients, one per node incidence
};

struct State {
  double t = 0;                      // simulated time, s
  long step_count = 0;
  VecX x;                            // 3 * nodes, positions (integrate)
  VecX v;                            // 3 * nodes, velocities (solve, constraints)
  std::vector<Mat3> R;               // per element rotation (assemble)
  VecX force;                        // 3 * nodes: elastic + gravity + external at x0 (assemble)
  VecX external_force;               // 3 * nodes: applied loads, N (set by callers; kept)
  SparseMatrix system;               // free-DOF system matrix A of eq. 19 (assemble; see system_assembled)
  VecX rhs;                          // 3 * free: b of eq. 19 (assemble)
  VecX start_residual;               // 3 * free: b - A v0, v0 the start-of-step velocities (assemble;
                                     // corotational scenes only)
  VecX v_free;                       // 3 * free: unconstrained v* (solve)
  VecX v_start;                      // 3 * free: velocities at the start of the step (solve, Newton)
  RowTable rows;                     // constraint rows at the step's last SQP iterate (constraints); after
                                     // a step its strain rows' Jacobians are zero (no QP followed that
                                     // build; complete_strain_limit_jacobians with strain_row_buffers sets them)
  EnergyScreen energy_screen;        // energy limits: each element's last exact evaluation (skips far ones)
  std::vector<std::pair<uint64_t, double>> warm_start;  // sorted row key -> lambda (constraints)
  VecX constraint_impulse;           // 3 * nodes: J^T lambda of the last step's last QP (constraints),
                                     // the next Newton solve's predictor; storage kept (no allocation)
  bool has_constraint_impulse = false;  // the last step solved a QP with rows: constraint_impulse holds
  bool constraint_impulse_steady = false;  // ... and changed by at most 10 % from the step before's
                                           // (the predictor's condition, solve_constraints.cpp)
  bool impulse_predicted = false;    // this step's Newton solve included it (solve_newton)
  // rhs - system v_free at Newton's result, formed without a product (solve_newton; read by
  // solve_constraints in place of rhs, which Newton leaves as stage 1's b); known only then.
  VecX model_residual;
  bool model_residual_known = false;
  TouchedInverse touched_inverse;    // H^-1 on the nodes rows touch, per factorisation (constraints)
  long touched_inverse_step = 0;     // step_count when touched_inverse was first filled after a reset
  int touched_inverse_first_nodes = 0;  // its touched nodes after that first fill
  Delassus delassus;                 // W = J H^-1 J^T of the current SQP iteration (constraints)
  ActiveSetPgs active_set_pgs;       // PGS's active set and W_AA for a factored W (constraints)
  std::vector<int> touched_scratch, local_node;  // scratch of the constraint solve
  RowColumnCache row_columns;        // H^-1 J_i^T per row, per factorisation, when W is formed
                                     // from one solve per row (constraints)
  std::vector<const double*> row_column_scratch;
  StepScratch scratch;
  SparseMatrix sqp_system;           // H = A plus the constraints' curvature (solve, constraints)
  std::vector<double> curvature;     // per element: h sum lambda_i curvature_i of its rows, from
                                     // the last SQP iteration; H = A + sum_e curvature_e R Ke R^T
  std::vector<std::pair<int, Eigen::Matrix<double, 12, 12>>> curvature_blocks;  // per tet with
                                     // strain rows: h sum lambda_i K_i (strain_limit_curvature.hpp)
  // The last SQP iteration's rows and their linearisation point, whose curvature (above)
  // is computed only when a factorisation needs it (settle_curvature, stages.hpp): strain
  // rows' blocks cost 10 constraint evaluations per tet, and most SQP iterations end
  // without a refactorisation.
  RowTable curvature_rows;
  VecX curvature_point;
  bool curvature_pending = false;
  bool factor_curved = false;        // the last factorisation included curvature
  bool factor_exact = false;         // the solver holds this step's A (solve): factorised this step, or
                                     // kept with every rotation within 1e-12 of its own (solve_velocity.cpp),
                                     // or Newton's H bit for bit the matrix factorised (solve_newton.cpp)
  int factor_age = 0;                // steps since the last factorisation (solve)
  bool factor_unmoved = false;       // reused for this step with no rotation moved since it was made and
                                     // no curvature in it: this step's A, though factor_exact is false
                                     // (which also picks SQP paths); solves read its own values (solve)
  KeptTetHessians kept_tet_hessians;  // Newton's projected tet Hessians kept while their F stays
                                     // within solver.hessian_reuse_tolerance (solve_newton.cpp)
  bool newton_factor_spent = false;  // the last Newton step's preconditioned CG failed with the
                                     // factorisation: the next one factorises (solve_newton.cpp)
  int factor_sqp = -1;               // SQP iterations of the step that made the factorisation (-1: none
                                     // counted, or it refactorised within them) (constraints)
  bool keep_curved_factor = false;   // the last step converged in at most factor_sqp SQP iterations
                                     // with no refactorisation: a curved factorisation may serve
                                     // the next step (solver.curved_refactor_interval; constraints)
  std::vector<Mat3> factor_rotations;  // per element, the R of the last factorisation's A (solve);
                                     // cleared where a factorisation must not be reused (world.cpp)
  std::vector<double> stiffness_scale;  // per element: its R Ke R^T's weight in A (0: none) (assemble)
  bool system_assembled = false;     // whether `system` holds this step's A (assemble_system_matrix;
                                     // on hyperelastic steps Newton's last H after solve_newton,
                                     // and before it only A's diagonal when no linear element is awake);
                                     // else A is applied element by element (multiply_step_system)
  std::vector<std::vector<Vec3>> surface;  // per body, deformed surface vertices (surface)
  BodySurfaces body_surfaces;        // per body, surface BVH refitted at the SQP iterate (constraints, body contact)
  StepProfile profile;               // of the last step
  SleepState sleep;                  // per body sleeping (World::step, engine/sleep/sleep.hpp)
  std::vector<Attachment> attachments;  // surface points held at targets (set by callers: ui/ grabs)
  double step_violation = 0;         // the worst constraint violation at the step's end, over its
                                     // tolerance (1: at it; 0 without constraints) (constraints);
                                     // after a refused step, its last attempt's
  double step_limit_violation = 0;   // the same without attachment gaps: the divergence test's
  bool last_step_within_limits = true;  // the last accepted step ended within every limit's tolerance
                                        // (step_limit_violation <= 1; World::attempt_step, rolled back
                                        // with a failed step): the SQP may then extend its cap once
                                        // (solve_constraints); edits between steps do not touch it
  IterationCaps caps;                // lower iteration caps for the next step (set by callers: the
                                     // real-time budget, engine/realtime/); 0 = the scene's
};

}  // namespace sinew
