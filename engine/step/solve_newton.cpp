#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/solve/system_product.hpp"
#include "engine/step/hyperelastic_derivatives.hpp"
#include "engine/step/stages.hpp"

namespace sinew {
namespace {

// Positions at the end of the step from free velocities: x0 + h v for free nodes, x0 for
// fixed ones, and driven nodes where their prescribed motion puts them at t_end.
void positions_at(const Model& model, double t_end, const VecX& x0, const VecX& v_free, VecX& x) {
  x = x0;
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0) x.segment<3>(3 * n) += model.h * v_free.segment<3>(3 * f);
  for (const DrivenNodes& driven : model.driven)
    for (int n : driven.nodes) x.segment<3>(3 * n) = driven.position(model.rest_x.segment<3>(3 * n), t_end);
}

void gather_free(const Model& model, const VecX& full, VecX& free) {
  free.resize(3 * model.num_free);
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0) free.segment<3>(3 * f) = full.segment<3>(3 * n);
}

// Round-off of a change of Psi computed as sum_e (Psi_e(x') - Psi_e(x)): each energy
// density sums terms of size ~(mu + lambda) |F|^2 with |F|^2 ~ 3 near rest, so a difference
// carries an error of a few eps (mu + lambda) V_e. 32 eps sum_e (mu + lambda) 3 V_e bounds it
// with room for moderate stretch. Below it the sign of a change of Phi means nothing. By
// body (Body::rest_volume): a loop over the elements' references took 0.3 ms a step on
// cube_20.
double energy_noise(const Model& model) {
  double sum = 0;
  for (const Body& body : model.bodies) {
    if (!body.hyperelastic) continue;
    MaterialParameters params;
    params.young = body.material.E;
    params.poisson = body.material.nu;
    const LameParameters lame = lame_parameters(params);
    sum += (lame.mu + lame.lambda) * body.rest_volume;
  }
  return 32 * std::numeric_limits<double>::epsilon() * 3 * sum;
}

// Newton's remaining gradient, relative to the step's scale (Newton's own stopping test's),
// up to which the model handed to the constraint stage keeps it (the end of solve_newton):
// 0.1, as the forcing term of its inexact CG solves (those relative to the current gradient).
// Set from measurements, not derived: ordinary steps of the bunny_5 drop end at 7e-5 of the
// scale (median; p90 0.11, max 0.71), the steps that ran away at 1.6-2.0, and keeping the
// gradient below 1 still let one run away later (bench/results/README.md, session 39).
constexpr double kTrustedResidual = 0.1;

// The largest solver.hessian_reuse_tolerance (its default) at which Newton ends on the model's
// gradient after an unchecked CG step (below): what that leaves out grows with the kept
// Hessians' age. Measured on a settled hanging bar as a fraction of the step's scale, at
// 1e-3 / 1e-2 / 5e-2: 7e-8 / 1.3e-7 / 9.9e-7 (E 200 kPa), 2.8e-7 / 2.6e-6 / 1.9e-5 (E 2 MPa),
// against Newton's tolerance of 1e-6.
constexpr double kModelGradientReuseLimit = 1e-3;

// The smallest scale of Newton's residual: the elements' forces at this strain. With
// newton_tolerance 1e-6, Newton stops at the forces of a strain of 1e-12, far below anything
// visible and ~1000 x the gradient's round-off (the SNH finger at rest: 1e-14 N s, the forces
// of a strain of 6e-16).
constexpr double kRestStrainScale = 1e-6;

}  // namespace

// Backward Euler for hyperelastic bodies as the minimisation of the incremental potential
// (paper 003, sec. 6), in velocities v over free DOFs, x = x0 + h v:
//   Phi(v) = 1/2 v^T A0 v - b0^T v + Psi(x0 + h v)
// A0, b0 (assemble_system) hold mass, mass damping, gravity, applied loads and the linear
// corotational bodies; Psi sums the hyperelastic elements. Driven nodes sit at their
// prescribed end-of-step positions inside Psi. Then
//   grad Phi = A0 v - b0 + h dPsi/dx,   Hess Phi = A0 + h^2 d2Psi/dx2.
// Newton with backtracking (Armijo) line search, from the previous step's velocities, until
// |grad Phi| <= newton_tolerance max(|grad Phi(v0)|, |b0|, h |dPsi/dx(x0 + h v0)|) or the
// iteration cap.
//
// Hessian: projected (each point's d2Psi/dF2 with eigenvalues clamped at 0, paper 003
// sec. 5), which keeps the system SPD far from equilibrium. Projection also drops the
// negative curvature that stress gives the rotation modes (zero at rest, slightly negative
// under load), so projected Newton converges only linearly near the solution (ratio ~0.14
// per iteration on a hanging beam: 9 iterations for 1e-8 instead of 3). So once a full
// projected step has decreased Phi as its quadratic model predicted (actual >= half the
// predicted decrease), the following iterations use the exact Hessian, which converges
// quadratically; at a minimiser of Phi it is positive semi-definite. Back to projection
// for the rest of the step if the exact system cannot be factorised, gives no descent
// direction, or its full step is rejected by the line search.
//
// On exit the system and a right-hand side rhs describe a quadratic model around the result,
// so solve_constraints treats it like the linear path's v*: state.system = the last Hessian
// (factorised), rhs = H v - grad Phi, or H v where Newton left a large gradient (see the
// end), neither formed: the model is handed on as its residual rhs - H v
// (state.model_residual; state.rhs stays stage 1's). With the predictor (below) the result is
// not that model's minimiser (its gradient there holds J^T lambda_0), and solve_constraints
// starts its first QP with the model's own Newton step.
bool solve_newton(const Model& model, LinearSolver& solver, State& state) {
  const SolverDesc& cfg = model.solver;
  const double t_end = state.t + model.h;
  StepScratch& scratch = state.scratch;  // kept storage: a warm step allocates nothing
  const VecX& x0 = scratch.newton_x0 = state.x;
  // A0 moves to the scratch by a swap (copying the matrix took 0.3 ms a step on cube_20):
  // state.system receives H at every factorisation, and A0 back if Newton fails. Until the
  // first factorisation it holds no matrix of this step (an earlier step's storage, or none
  // on the first step): nothing reads it there, and factorize_step_system's
  // assemble_system_matrix returns at once (stage 1 assembled this step's A already).
  scratch.newton_A0.swap(state.system);
  const SparseMatrix& A0 = scratch.newton_A0;
  // Without a linear element awake (every stiffness_scale 0) A0 is the mass and mass
  // damping on its diagonal alone (assemble_system_matrix writes that diagonal and leaves
  // the other values stale, unread): its products then take one pass over that diagonal
  // instead of the whole pattern (bunny_5: 1.1 M instructions a product, three a step), with
  // the same bits for finite velocities (a non-finite one fails the step either way).
  VecX& A0_diagonal = scratch.newton_A0_diagonal;
  const bool A0_is_diagonal = system_is_mass_diagonal(state);
  if (A0_is_diagonal) {
    A0_diagonal.resize(3 * model.num_free);
    for (int i = 0; i < 3 * model.num_free; ++i) A0_diagonal[i] = A0.valuePtr()[model.pattern.diagonal[i]];
  }
  const auto multiply_A0 = [&](const VecX& in, VecX& out) {
    if (A0_is_diagonal) multiply_diagonal(A0_diagonal, in, out);
    else multiply_node_blocked(A0, in, out);  // in parallel: Eigen's product is one thread
  };
  // H = A0 before the Hessians are added. Every matrix of a step has the stage model's one
  // pattern (SystemPattern; World::apply_sleeping_set drops Newton's kept matrices when the
  // awake set, and with it the pattern, changes), so once H holds it only the values are
  // written: with A0 diagonal, zeros and that diagonal (A0's other values are stale); else
  // A0's values. A whole copy moved 2.3 MB a step on bunny_5 (values, row
  // indices, column starts). The column starts are compared (n + 1 ints) as a cheap guard.
  // pattern_only: only the pattern is wanted (the caller writes every value).
  const auto start_from_A0 = [&](SparseMatrix& to, bool pattern_only = false) {
    if (to.rows() != A0.rows() || to.nonZeros() != A0.nonZeros() || !to.isCompressed() || !A0.isCompressed() ||
        !std::equal(A0.outerIndexPtr(), A0.outerIndexPtr() + A0.outerSize() + 1, to.outerIndexPtr())) {
      to = A0;
      if (!A0_is_diagonal) return;  // else its values are written below
    } else {
      assert(std::equal(A0.innerIndexPtr(), A0.innerIndexPtr() + A0.nonZeros(), to.innerIndexPtr()));
    }
    if (pattern_only) return;
    double* values = to.valuePtr();
    if (!A0_is_diagonal) {
      std::copy(A0.valuePtr(), A0.valuePtr() + A0.nonZeros(), values);
      return;
    }
    std::fill_n(values, A0.nonZeros(), 0.0);
    for (int i = 0; i < 3 * model.num_free; ++i) values[model.pattern.diagonal[i]] = A0_diagonal[i];
  };
  const VecX& b0 = scratch.newton_b0 = state.rhs;
  // Predictor (solver.newton_predictor "impulse"): the last step's constraint impulse
  // J^T lambda joins b0 as a fixed force, so Newton minimises the Lagrangian at the last
  // multipliers, Phi(v) - (J^T lambda)^T v: a body resting on the ground is solved as held
  // there, not falling through it. solve_constraints then starts from the true model's
  // residual (it is not zero at this v) and its QP finds the whole lambda, so the force
  // stays only where the QP keeps it. Without it, a step that held a body took three QPs
  // against an older factorisation: one for the impulse Newton left out, two for that
  // factor's error on it (the bunny_5 drop at rest; docs/ARCHITECTURE.md, stage 2-3').
  VecX& predicted = scratch.newton_predicted_impulse;
  state.impulse_predicted = cfg.newton_predictor == "impulse" && state.has_constraint_impulse && state.constraint_impulse_steady && !state.warm_start.empty();
  if (state.impulse_predicted) {
    gather_free(model, state.constraint_impulse, predicted);
    scratch.newton_b0 += predicted;
  }
  const double noise = energy_noise(model);
  long hyperelastic_elements = 0;  // evaluated per assembly and per line-search trial (StepWork)
  for (const Body& body : model.bodies) hyperelastic_elements += body.hyperelastic ? body.num_elements() : 0;
  VecX &v = scratch.newton_v, &x = scratch.newton_x, &dPsi = scratch.dPsi, &gradient = scratch.gradient;
  VecX &quadratic_gradient = scratch.quadratic_gradient, &direction = scratch.direction, &trial = scratch.trial;
  VecX &A0_direction = scratch.A0_direction, &dPsi_trial = scratch.dPsi_trial;
  std::vector<double> &psi = scratch.psi, &psi_trial = scratch.psi_trial, &force2 = scratch.force2;
  std::vector<double>& force2_trial = scratch.force2_trial;
  // The line search evaluates energies and gradient at its trials: the accepted trial then
  // needs no second pass over the elements for the next iteration's residual, and a last
  // iterate (converged, or at the cap) none at all (one Newton iteration a step assembled
  // the gradient again after its line search).
  bool derivatives_at_v = false;  // psi, force2 and dPsi are those at v, from the line search
  // At the iteration cap, after a full step along a preconditioned CG direction that the line
  // search left unchecked (its predicted decrease within the energies' round-off), gradient
  // holds the quadratic model's gradient at v, g + H d = -(CG's residual), and no pass over
  // the elements evaluates Phi's own there: the loop ends at v whatever the gradient, which
  // only goes on as the model's residual (below). What that leaves out is (H_exact - H) d, H's
  // tet Hessians being projected and kept from a nearby F: measured at 3e-7 of the step's
  // scale on cube_20 at rest and at most 7e-8 on a settled hanging bar, within Newton's own
  // tolerance (1e-6), where a converged Newton would stop too
  // (test_newton_residual_handoff.cpp checks it), at hessian_reuse_tolerance 1e-3 (its
  // default); with older kept Hessians it can exceed it, so the path is taken only up to
  // kModelGradientReuseLimit. A resting cube_20's step made two passes
  // (0.8-0.9 ms each on 2 threads): now one.
  bool model_gradient_at_v = false;
  int model_gradient_steps = 0;  // steps that ended on the model's gradient (stats)
  gather_free(model, state.v, v);
  state.v_start = v;

  int newton = 0;
  double first_norm = -1;
  bool ok = true, factorised = false, exact = false;
  int exact_steps = 0;  // Newton directions from the exact Hessian (stats: newton_exact)
  SparseMatrix& H = scratch.newton_H;  // A0 plus the Hessian of Psi, copied from A0 by each assembly
  // Newton's matrix is the Hessian of Phi alone. The previous step's constraint curvature
  // (which factorize_step_system would add) has no term in Phi's gradient: with it the
  // Newton steps were wrong and every step ran to the iteration cap once energy rows had
  // been active (found by tools/stress). Its rows stay in state.curvature_rows: the
  // constraint stage's matrix gets their curvature back (the end of this function).
  // (Only with refactor_interval 1: with a longer one the curved factorisation would go on
  // preconditioning the next steps' Newton CG, and a resting body's unchanged H would never
  // match the factorised matrix again.)
  const bool rows_with_curvature =
      cfg.refactor_interval == 1 && state.curvature_pending &&
      state.curvature_rows.count(RowKind::Energy) + state.curvature_rows.count(RowKind::Strain) > 0;
  state.curvature.clear();
  state.curvature_blocks.clear();
  state.curvature_pending = false;
  // refactor_interval > 1: between factorisations the Newton directions come from
  // conjugate gradients on this H preconditioned with the last factorisation (a few solves
  // instead of a factorisation while H changes slowly), to pcg_tolerance; the constraint
  // solve then refines with that older factor as it does on the linear path.
  // Cleared when a direction is rejected: the redo with the projected Hessian must factorise
  // it, not precondition with a factor that failed or was of an indefinite exact Hessian.
  // After a step whose preconditioned CG failed (state.newton_factor_spent), the first
  // Newton iteration factorises and the later ones precondition with that factorisation.
  state.factor_unmoved = false;  // H changes with the positions, not only with rotations
  solver.keep_factored_matrix(true);  // for holds_factor_of below
  const bool factor_spent = state.newton_factor_spent;
  bool may_reuse = state.step_count > 0 && solver.uses_cholmod() && !factor_spent &&
                   ++state.factor_age < cfg.refactor_interval;
  bool preconditioning = false;
  int preconditioned_iterations = 0;
  // Whether a preconditioned CG of this step stopped unconverged (at its cap, or at a
  // direction without positive curvature; H was then factorised): the factorisation no
  // longer preconditions this body's Hessians well, and the next step factorises before
  // trying it. Not for the exact Hessian, whose CG stops on its own indefiniteness whatever
  // the factorisation.
  bool pcg_failed = false;
  int pcg_fallbacks = 0;
  bool factorised_this_step = false, direction_rejected = false;
  // The assembled H moves into state.system by a swap (a copy took 0.1-0.3 ms a step); H's
  // storage then holds no Hessian until the next assembly.
  bool hessian_in_system = false;
  auto factorize = [&](bool allow_reuse = true) {
    StageTimer timer(state.profile, Stage::Factorize);
    assert(state.system_assembled);  // else factorize_step_system would assemble A over H
    if (!hessian_in_system) state.system.swap(H);
    hessian_in_system = true;
    if (allow_reuse && may_reuse) {
      preconditioning = factorised = true;
      state.factor_exact = false;
      if (!factorised_this_step)
        state.profile.skipped[static_cast<int>(Stage::Factorize)] = "preconditioning with the factorisation of an earlier step";
      return true;
    }
    preconditioning = false;
    state.profile.skipped[static_cast<int>(Stage::Factorize)].clear();
    if (solver.holds_factor_of(state.system)) {
      // H is the matrix of the last factorisation, bit for bit (a body at rest keeps every
      // tet Hessian, and A0 stays the mass diagonal): its factor is what factorising H again
      // would make, so it stands as this step's, with every column solved with it (cube_20
      // at rest refactorised a 2.97M-entry factor every refactor_interval steps, ~53 ms on
      // 2 threads, to the same values).
      keep_factorisation_as_current(model, state, "Newton's Hessian unchanged since the last factorisation");
      // A factorisation made at an earlier iteration of this step stays reported as made.
      if (factorised_this_step) state.profile.skipped[static_cast<int>(Stage::Factorize)].clear();
      state.factor_curved = false;
      factorised = true;
    } else {
      factorised = factorize_step_system(model, solver, state);
      state.factor_exact = !state.factor_curved;
    }
    factorised_this_step = factorised_this_step || factorised;
    // The factorisation that replaced a spent one serves this step's later iterations
    // (unless a direction was rejected: then each iteration factorises, as in any step).
    if (factor_spent && factorised && allow_reuse && !direction_rejected) may_reuse = true;
    return factorised;
  };
  // with_hessian false: energies and gradient only (state.system keeps the factorised Hessian).
  // The constraint stage's QPs on H plus the curvature of the last step's limit rows, as the
  // linear path's do (its factorisation carries it from step to step, solve_velocity.cpp): on
  // H alone they started every step without it and got it only by refactorising once they
  // stalled, and an SNH body whose strain limits carry its weight (paper 001's fig. 2 beam in
  // SNH) ended 50 of 60 steps at the SQP cap (docs/ARCHITECTURE.md, "Strain limits on
  // hyperelastic bodies"). H is the matrix Newton factorised last (state.system), or, when
  // Newton converged at its start, the assembled one. Rows without a multiplier give no
  // curvature: then H alone, as factorize() would. v* stays Newton's minimiser of Phi
  // (factor_exact stays true: ending the step at v* when it meets every row is still right).
  int curved_factorisations = 0;
  // The last step's limit rows back as pending, their curvature settled: whether it is nonzero.
  auto settle_limit_curvature = [&] {
    state.curvature_pending = true;
    settle_curvature(model, state);
    return has_curvature(state);
  };
  // state.system plus the settled curvature (factorize_step_system adds it).
  auto factorize_curved = [&] {
    state.profile.skipped[static_cast<int>(Stage::Factorize)].clear();
    const bool made = factorize_step_system(model, solver, state);
    curved_factorisations += made;
    return made;
  };
  auto factorize_with_curvature = [&]() {
    StageTimer timer(state.profile, Stage::Factorize);
    if (!settle_limit_curvature()) return factorize(false);
    if (!hessian_in_system) state.system.swap(H);
    hessian_in_system = true;
    const bool made = factorize_curved();
    if (made) {
      factorised = true;
      preconditioning = false;
    }
    return made;
  };
  long hessians_formed = 0;  // kept Hessians: tets that formed theirs afresh (stats)
  auto assemble = [&](bool with_hessian = true) {
    positions_at(model, t_end, x0, v, x);
    StageTimer timer(state.profile, Stage::Assemble);
    KeptTetHessians* kept = cfg.hessian_reuse_tolerance > 0 ? &state.kept_tet_hessians : nullptr;
    // Every Hessian kept and A0 diagonal: the pass writes H's values whole (the kept sum) and
    // A0's diagonal is added after, the same sums (d + k = k + d) without zeroing the values
    // first (a pass over 8.9 MB a step on cube_20).
    const bool overwrite = with_hessian && !exact && kept && A0_is_diagonal && keeps_every_hessian(model, *kept);
    if (with_hessian) {
      start_from_A0(H, overwrite);
      hessian_in_system = false;
    }
    hyperelastic_derivatives(model, x, exact, psi, force2, dPsi, with_hessian ? H.valuePtr() : nullptr,
                             scratch.node_gradients, kept, cfg.hessian_reuse_tolerance, overwrite);
    if (overwrite)
      for (int i = 0; i < 3 * model.num_free; ++i) H.valuePtr()[model.pattern.diagonal[i]] += A0_diagonal[i];
    state.profile.work.elements += hyperelastic_elements;
    if (kept && with_hessian && !exact) hessians_formed += kept->formed;
  };
  for (;; ++newton) {
    // At the iteration cap the loop ends after this assembly whatever the residual, and a
    // factorisation is already there: its Hessian would go unused (one Newton iteration
    // per step assembled it twice).
    const int newton_cap = IterationCaps::effective(cfg.newton_max_iterations, state.caps.newton);
    const bool from_model = model_gradient_at_v && newton == newton_cap;
    model_gradient_at_v = false;
    if (!derivatives_at_v && !from_model) assemble(!(newton == newton_cap && factorised));
    // Undefined energy (an inverted neo_hookean element) at the warm start: start from the
    // positions of the step's start instead (v = 0); if the energy is undefined there too,
    // the step has no incremental potential to minimise and fails.
    if (newton == 0 && !std::all_of(psi.begin(), psi.end(), [](double p) { return std::isfinite(p); })) {
      if (v.isZero(0)) {
        ok = false;
        break;
      }
      v.setZero();
      assemble();
      if (!std::all_of(psi.begin(), psi.end(), [](double p) { return std::isfinite(p); })) {
        ok = false;
        break;
      }
    }
    if (from_model) {
      ++model_gradient_steps;  // gradient already holds the model's (set with the step below)
    } else {
      multiply_A0(v, quadratic_gradient);
      quadratic_gradient -= b0;
      gradient = quadratic_gradient + model.h * dPsi;
    }
    const double norm = gradient.norm();
    if (!std::isfinite(norm)) {
      ok = false;
      break;
    }
    // Scale of the residual: the largest of the first gradient, the step's momentum and
    // external forces (b0), and the elements' forces before they cancel at the nodes,
    // h sqrt(sum_e |dPsi_e/dx|^2). A body at rest under stress (held, driven, loaded) has a
    // tiny net gradient but large element forces, whose round-off (~eps of them) bounds
    // how small the assembled gradient can get: measured against the net gradient alone
    // the tolerance could be unreachable. And at least the forces a strain of
    // kRestStrainScale would make: a body at rest with no load, momentum or stress (zero
    // gravity) has all three at round-off, its gradient too, and Newton ran to its cap
    // every step (20 iterations, 0.4-3 x the "scale": the SNH finger without its load).
    if (first_norm < 0) {
      double element_forces = 0;
      for (double f2 : force2) element_forces += f2;  // fixed order
      first_norm = std::max({norm, b0.norm(), model.h * std::sqrt(element_forces),
                             kRestStrainScale * model.h * model.hyperelastic_unit_strain_forces});
    }
    // Converged: the factorisation of the last iterate's Hessian stays (one is made if the
    // start was already converged, for solve_constraints).
    state.profile.violation["newton_residual"] = first_norm > 0 ? norm / first_norm : 0.0;
    if (norm <= cfg.newton_tolerance * first_norm || norm == 0 || newton == newton_cap) {
      // Not factorised yet (converged at the start): with limit rows from the last step, the
      // one factorisation made is H plus their curvature (below), not H and then that.
      if (!factorised) ok = rows_with_curvature ? factorize_with_curvature() : factorize();
      if (!ok && exact) {  // the exact Hessian at the result is not SPD: leave a projected one
        exact = false;
        assemble();
        ok = factorize();
      }
      break;
    }
    // The Hessian at v (with its energies and gradient again: the same bits as the trial's).
    if (derivatives_at_v) assemble();
    derivatives_at_v = false;
    bool usable = factorize();
    double slope = 0;
    bool direction_from_pcg = false;  // CG's residual is then the model's at v + direction
    if (usable) {
      scratch.negative_gradient = -gradient;
      int iterations = -1;  // solve_preconditioned starts from direction = 0 itself
      if (preconditioning) {
        {
          StageTimer timer(state.profile, Stage::Solve);
          // Past this many iterations a factorisation is cheaper (one costs 20-70 solves on
          // the meshes of sinew_bench_hyperelastic). The tolerance is relative to the step's
          // scale (first_norm), not to this gradient alone: a body at rest has a tiny net
          // gradient, and 1e-8 of it asked for more CG iterations than Newton's own
          // tolerance (1e-6 of the scale) could ever use. Capped so that the CG residual
          // stays below a tenth of the gradient (inexact Newton with forcing term <= 0.1,
          // whatever pcg_tolerance and newton_tolerance are; never a zero direction).
          iterations = solver.solve_preconditioned(state.system, scratch.negative_gradient, direction, cfg.pcg_tolerance,
                                                   kNewtonPcgCap, std::min(first_norm, 0.1 * norm / cfg.pcg_tolerance));
        }
        // Too slow or no descent: this H is far from the factorised one; factorise it.
        if (iterations < 0) {
          ++pcg_fallbacks;
          pcg_failed = pcg_failed || !exact;
          usable = factorize(false);
        }
      }
      if (iterations >= 0) {
        preconditioned_iterations += iterations;
        direction_from_pcg = true;
      } else if (usable) {
        StageTimer timer(state.profile, Stage::Solve);
        direction.setZero(v.size());
        solver.solve(scratch.negative_gradient, direction);
      }
      if (usable) {
        slope = gradient.dot(direction);
        usable = slope < 0;
      }
    }
    if (!usable) {
      if (!exact) {
        ok = false;
        break;
      }
      exact = false;  // redo this iteration with the projected Hessian
      may_reuse = false;
      direction_rejected = true;
      --newton;
      continue;
    }
    StageTimer timer(state.profile, Stage::Solve);
    // Backtracking: halve until Phi decreases enough (Armijo, c = 1e-4). The change of Phi
    // along the step is formed without subtracting totals, so that it stays accurate when
    // it is tiny next to Phi itself:
    //   Phi(v + a d) - Phi(v) = a (A0 v - b0).d + a^2/2 d^T A0 d + sum_e (Psi_e(x') - Psi_e(x)).
    // An undefined energy (inverted neo_hookean element) is +infinity and always rejected.
    // Near the solution the predicted decrease -slope = g^T H^-1 g (the Newton decrement
    // squared) falls below the round-off of the energies (energy_noise): the test would
    // then reject good steps by noise and stall Newton at a tiny step length. There the
    // full Newton step is taken (the quadratic model is exact to that precision).
    multiply_A0(direction, A0_direction);
    const double linear_term = quadratic_gradient.dot(direction), curvature = direction.dot(A0_direction);
    auto change_at = [&](double a) {
      trial = v + a * direction;
      positions_at(model, t_end, x0, trial, x);
      hyperelastic_derivatives(model, x, false, psi_trial, force2_trial, dPsi_trial, nullptr, scratch.node_gradients);
      state.profile.work.elements += hyperelastic_elements;
      double change = a * linear_term + 0.5 * a * a * curvature;
      for (int e = 0; e < model.num_elements; ++e) change += psi_trial[e] - psi[e];  // fixed order
      return change;
    };
    double alpha = 1;
    bool trusted = true;  // the quadratic model predicted this step well
    if (-slope > noise) {
      // Predicted decrease of a full step: -(g.d + 1/2 d^T H d) = -slope / 2.
      double change = change_at(alpha);
      trusted = change <= 0.25 * slope;
      int k = 0;
      while (k < 20 && !(change <= 1e-4 * alpha * slope)) alpha *= 0.5, ++k, change = change_at(alpha);
      // No acceptable step along a descent direction: Newton cannot progress from here.
      if (k == 20) break;
    }
    exact_steps += exact;  // this direction came from the exact Hessian and is taken
    exact = alpha == 1 && trusted;
    if (-slope > noise) {  // the last trial is the accepted one: v and its derivatives
      v.swap(trial);
      psi.swap(psi_trial);
      force2.swap(force2_trial);
      dPsi.swap(dPsi_trial);
      derivatives_at_v = true;
    } else {
      v += alpha * direction;  // alpha is 1: no trial was evaluated
      if (direction_from_pcg && newton + 1 == newton_cap && cfg.hessian_reuse_tolerance <= kModelGradientReuseLimit) {
        gradient = -solver.preconditioned_residual();
        model_gradient_at_v = true;
      }
    }
  }
  if (!ok) state.system = A0;  // the matrix (its pattern) for the caller's retry
  // The quadratic model that solve_constraints continues from: H around v, of Phi itself
  // (H v - rhs = grad Phi) when Newton brought its gradient within kTrustedResidual of the
  // step's scale; else with v as its minimiser (H v - rhs = 0), or with the predictor the
  // Lagrangian's stationary point at the predicted force (H v - rhs = J^T lambda_0, the force
  // the QP must find again), as when no row is active and v ends the step. Kept whole, a
  // large remaining gradient made the SQP's first step from v the model's whole Newton step,
  // never line-searched on Phi, wherever a single row was active: with one Newton iteration
  // a step, where the Hessian at the step's start mispredicts the gradient most, a Stable
  // Neo-Hookean bunny_5 dropped from 0.5 m had nodes pushed to 5 km/s at its landing
  // (docs/ARCHITECTURE.md, stage 2-3'). Below it the remaining step is small beside the one
  // taken, and keeping it refines the result (a resting body's constrained steps).
  // The model goes on as its residual at v, r = rhs - H v = -grad Phi (or 0), less the
  // predicted force (state.model_residual), which needs no product with H: rhs itself is not
  // formed (solve_constraints took r back from it with a second product; each ~0.3 ms a step
  // on cube_20, and r came out with the round-off of H v, eps |H v|, where r is tiny at rest).
  if (ok) {
    VecX& r = state.model_residual;
    if (gradient.norm() <= kTrustedResidual * first_norm) r = -gradient;
    else r.setZero(v.size());
    if (state.impulse_predicted) r -= predicted;
    state.model_residual_known = true;
    state.v_free = v;
    for (int n = 0; n < model.num_nodes; ++n) {
      const int f = model.free_index[n];
      state.v.segment<3>(3 * n) = f >= 0 ? Vec3(v.segment<3>(3 * f)) : Vec3::Zero();
    }
    // Driven nodes move with the step's mean velocity, so that integrate_positions puts
    // them at their prescribed positions.
    for (const DrivenNodes& driven : model.driven)
      for (int n : driven.nodes)
        state.v.segment<3>(3 * n) =
            (driven.position(model.rest_x.segment<3>(3 * n), t_end) - x0.segment<3>(3 * n)) / model.h;
  }
  // Newton factorised H for its own iterations: the QPs' factorisation of that H (not a newer
  // assembly) plus the curvature, one more this step. If even H alone no longer factorises
  // (it did a moment ago), the step fails as Newton's would.
  if (ok && rows_with_curvature && curved_factorisations == 0 && !preconditioning) {
    StageTimer timer(state.profile, Stage::Factorize);
    if (settle_limit_curvature() && !(ok = factorize_curved())) state.system = A0;  // for the caller's retry
  }
  // On every Newton step of a scene with limits, 0 included (profile_map.hpp).
  const bool has_limits = model.has_strain_limits || std::any_of(model.bodies.begin(), model.bodies.end(), [](const Body& b) {
                            return b.energy_limit.enabled;
                          });
  if (has_limits) state.profile.iterations["newton_curved_factorisations"] += curved_factorisations;
  // A factorisation with which CG failed is spent: the next step factorises first. During
  // an impact H changes so fast that even a factorisation one step old leaves CG
  // unconverged after 12 iterations (bunny_5's landing: six steps in a row ran 12
  // iterations, then factorised anyway). Also counting solves that converged in 9-12
  // iterations as spent was tried: 3.7 % more instructions on bunny_5's drop with Newton
  // converged to 1e-6 (more factorisations than the CG iterations they saved), against
  // 0.35 % for failures alone; with one Newton iteration a step -4.5 and -4.3 %.
  state.newton_factor_spent = pcg_failed;
  state.profile.iterations["newton"] += newton;
  // With refactor_interval > 1 on every Newton step, 0 included: a name first met in a warm
  // step would allocate (profile_map.hpp).
  if (cfg.refactor_interval > 1) {
    state.profile.iterations["newton_pcg_fallbacks"] += pcg_fallbacks;
    state.profile.iterations["newton_model_gradient"] += model_gradient_steps;
  }
  if (exact_steps) state.profile.iterations["newton_exact"] += exact_steps;
  if (preconditioned_iterations) state.profile.iterations["newton_pcg"] += preconditioned_iterations;
  // On every Newton step when Hessians are kept, 0 included (profile_map.hpp).
  if (cfg.hessian_reuse_tolerance > 0) state.profile.iterations["newton_hessians_formed"] += hessians_formed;
  // Reported on every Newton step, 0 included: a name first met in a warm step would
  // allocate (profile_map.hpp).
  state.profile.iterations["newton_predicted"] += state.impulse_predicted ? 1 : 0;
  // solver.linear "pcg": its counts come from World::attempt_step.
  return ok;
}

}  // namespace sinew
