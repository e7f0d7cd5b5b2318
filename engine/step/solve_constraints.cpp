#include <algorithm>
#include <cassert>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/constraints/attachment_rows.hpp"
#include "engine/constraints/body_contact_rows.hpp"
#include "engine/constraints/contact_rows.hpp"
#include "engine/constraints/energy_limit.hpp"
#include "engine/constraints/lcp_pgs.hpp"
#include "engine/constraints/strain_limit_rows.hpp"
#include "engine/step/sqp_kkt_stop.hpp"
#include "engine/step/sqp_merit.hpp"
#include "engine/step/stages.hpp"

namespace sinew {
namespace {

// Builds every kind's rows at the iterate (positions x = x0 + h v, velocities v, obstacles
// at t_end, the end of the step); returns the worst violation relative to each kind's
// tolerance (<= 1 means converged). The strain rows' Jacobians are deferred: the caller
// completes them (complete_strain_limit_jacobians) before it uses them. A new kind of
// constraint adds a line here, not a branch in the solver.
// Contact: on the first iteration (k = 0) any predicted penetration counts as a violation,
// so the LCP is solved on every step a contact closes: friction rows have no violation of
// their own, and waiting for the penetration to exceed the tolerance would let bodies slide
// freely on the steps in between (and sink, when g h^2 < contact_tolerance).
// `limits`: the same worst without the attachments' gaps (the divergence test's measure: a
// grab dragged where the body cannot follow is a wish, not a diverged step).
double build_rows(const Model& model, double t_end, int k, const VecX& x, const VecX& v,
                  const std::vector<double>& strain_cut_gaps,
                  const std::vector<uint64_t>& keep, const std::vector<Attachment>& attachments, RowTable& rows,
                  BodySurfaces& surfaces, EnergyScreen& screen, StepScratch& sc, StepProfile& profile,
                  double& limits) {
  RowTable& contacts = sc.contact_rows;
  rows.clear();
  // Limits and contacts share no data: built side by side (the creature: 40 and 55 us a
  // build on 2 threads, 4-5 builds a step), contacts into their own table, appended after
  // the limits' so that the rows come in the same order as one after the other.
  contacts.clear();
  const bool contact = !model.obstacles.empty() || model.bodies.size() > 1;
  double energy = -1, strain = -1, penetration = 0;
  tbb::parallel_invoke(
      [&] {
        energy = add_energy_limit_rows(model, x, model.solver.activation_margin, keep, rows, &screen,
                                       &sc.energy_row_buffers);
        if (model.has_strain_limits)
          strain = add_strain_limit_rows(model, x, model.solver.strain_activation_margin, keep, rows,
                                         &sc.strain_row_buffers, StrainJacobians::Deferred, &strain_cut_gaps);
      },
      [&] {
        if (contact)
          penetration = std::max(
              add_contact_rows(model, t_end, x, v, keep, contacts, ContactSearch::BroadPhase, &sc.contact_row_buffers)
                  .deepest,
              add_body_contact_rows(model, x, v, keep, surfaces, contacts, ContactSearch::BroadPhase,
                                    &sc.body_contact_row_buffers)
                  .deepest);
      });
  rows.append(contacts);
  profile.violation["energy"] = std::max(0.0, energy);
  double worst = energy / model.solver.sqp_tolerance;
  if (model.has_strain_limits) {
    profile.violation["strain"] = std::max(0.0, strain);
    worst = std::max(worst, strain / model.solver.strain_tolerance);
  }
  if (contact) {
    profile.violation["penetration"] = penetration;
    worst = std::max(worst, penetration / model.solver.contact_tolerance);
    if (k == 0 && penetration > 0) worst = std::max(worst, 2.0);
  }
  limits = worst;
  if (!attachments.empty()) {
    const double gap = add_attachment_rows(model, attachments, x, rows);
    profile.violation["attachment"] = gap;
    worst = std::max(worst, gap / model.solver.contact_tolerance);
  }
  return worst;
}

// A step that solved no QP: PGS and the SQP's factorisation, solve and merit stages did
// nothing (their timers, if any ran, timed no work), and the stats say why.
void skip_qp_stages(StepProfile& profile, const char* reason) {
  for (const Stage stage : {Stage::Pgs, Stage::SqpFactorize, Stage::SqpSolve, Stage::SqpMerit})
    profile.skipped[static_cast<int>(stage)] = reason;
}

bool has_constraints(const Model& model, const State& s) {
  return !s.attachments.empty() || !model.obstacles.empty() || model.bodies.size() > 1 || model.has_strain_limits ||
         std::any_of(model.element_Umax.begin(), model.element_Umax.end(), [](double u) { return u > 0; });
}

double warm_lambda(const std::vector<std::pair<uint64_t, double>>& warm, uint64_t key) {
  const auto it = std::lower_bound(warm.begin(), warm.end(), std::make_pair(key, -1e300));
  return (it != warm.end() && it->first == key) ? it->second : 0.0;
}

// Whether the QP's rows are those of the last QP of this step (warm: its keys, sorted).
bool same_rows_as_last_qp(const RowTable& rows, const std::vector<std::pair<uint64_t, double>>& warm) {
  if (static_cast<size_t>(rows.size()) != warm.size()) return false;
  for (int i = 0; i < rows.size(); ++i) {
    const auto it = std::lower_bound(warm.begin(), warm.end(), std::make_pair(rows.key[i], -1e300));
    if (it == warm.end() || it->first != rows.key[i]) return false;
  }
  return true;
}

void scatter_free(const Model& model, const VecX& free, VecX& full) {
  for (int n = 0; n < model.num_nodes; ++n) {
    const int f = model.free_index[n];
    full.segment<3>(3 * n) = f >= 0 ? Vec3(free.segment<3>(3 * f)) : Vec3::Zero();
  }
}

// Per row h / (its kind's SQP tolerance): PGS's residual (a velocity, w = J v) times it is
// the change of C over the step as a fraction of what SQP accepts.
void residual_weights(const SolverDesc& cfg, double h, const RowTable& rows, Eigen::Ref<VecX> weight) {
  for (int i = 0; i < rows.size(); ++i) weight[i] = h / row_tolerance(cfg, rows.kind[i]);
}

// out += J u over the rows' stencils (u: free velocities).
void add_jacobian_times(const Model& model, const RowTable& rows, const VecX& u, Eigen::Ref<VecX> out) {
  for (int i = 0; i < rows.size(); ++i)
    for (int k = rows.begin[i]; k < rows.begin[i + 1]; ++k)
      if (const int f = model.free_index[rows.nodes[k]]; f >= 0) out[i] += rows.jac[k].dot(u.segment<3>(3 * f));
}

// out = J^T lambda on the free DOFs, lambda = rows.lambda.
void apply_jacobian_transpose(const Model& model, const RowTable& rows, VecX& out) {
  out.setZero(3 * model.num_free);
  for (int i = 0; i < rows.size(); ++i)
    for (int k = rows.begin[i]; k < rows.begin[i + 1]; ++k)
      if (const int f = model.free_index[rows.nodes[k]]; f >= 0) out.segment<3>(3 * f) += rows.lambda[i] * rows.jac[k];
}

// Whether no row carries curvature (energy and strain rows do: element >= 0): contacts,
// friction and attachments, linear in the positions on planes.
bool rows_without_curvature(const RowTable& rows) {
  return std::all_of(rows.element.begin(), rows.element.end(), [](int e) { return e < 0; });
}

// Whether h (v - v0) moves some node further than its body's contact margin.
bool strays_beyond_margin(const Model& model, const VecX& v0, const VecX& v) {
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0 &&
        model.h * (v - v0).segment<3>(3 * f).norm() > contact_margin(model, model.node_body[n]))
      return true;
  return false;
}

// W = J H^-1 J^T for this iteration's rows into s.delassus. From H^-1 on the touched
// nodes (touched_inverse.hpp) when the nodes no earlier row of this factorisation touched
// cost at most one solve per row (3 per node); otherwise from one solve per row,
// Y = H^-1 J^T, whose columns are kept for the rows whose Jacobian does not change
// (row_column_cache.hpp). Returns the columns solved; `approximate` says whether W came
// from a kept G of an earlier factorisation (solver.delassus_reuse), `per_row` whether
// from the rows' columns (then in s.row_column_scratch: whole columns when
// s.row_columns.complete(), else right on the rows' stencils only, enough for W). Without
// `columns_cheaper` (the caller will not use Y beyond W) they may be solved partially.
int factor_delassus(const Model& model, LinearSolver& solver, State& s, bool& approximate, bool& per_row,
                    bool columns_cheaper) {
  approximate = false;
  per_row = false;
  const int m = s.rows.size();
  // The rows of the last per-row call, bit for bit, on the same factorisation: its columns
  // (in s.row_column_scratch) and the W built from them stand; nothing to look up (the
  // creature's settled QPs: the touched-node list and 99 lookups, ~30 us a QP).
  if (s.delassus.built_direct(m) && s.row_columns.repeats_last_call(s.rows)) {
    per_row = true;
    return 0;
  }
  std::vector<int>& touched = s.touched_scratch;
  touched.clear();
  for (const int node : s.rows.nodes)
    if (const int f = model.free_index[node]; f >= 0 && s.touched_inverse.local(f) < 0) touched.push_back(f);
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  const auto solve_many = [&](const auto& B, auto& X, const std::vector<int>* wanted,
                              const LinearSolver::ColumnPattern* pattern) { solver.solve_many(B, X, wanted, pattern); };
  if (3 * static_cast<int>(touched.size()) > m) {
    // Energy rows from node columns when a CHOLMOD factorisation serves several steps (PCG
    // keeps no factor: its columns would be solved again every step, and only to its
    // tolerance), at most 8 node columns per energy row and step of its life (the
    // creature's: 22-28 nodes for 3-6 rows at refactor_interval 4).
    const int node_budget = model.solver.refactor_interval > 1 && solver.uses_cholmod() ? 8 * model.solver.refactor_interval : 0;
    // Whole columns only where they serve beyond W (columns_cheaper: Y^T r and Y lambda
    // instead of solves); else right on the rows' stencils only (row_column_cache.hpp), where
    // the solver can skip the rest (a supernodal factor).
    const bool partial = !columns_cheaper && solver.honours_wanted_rows();
    const int solved = s.row_columns.columns(s.rows, model.free_index, 3 * model.num_free, solve_many,
                                             s.row_column_scratch, node_budget, partial);
    // Contacts on a plane keep their Jacobians, and so their columns, from one SQP
    // iteration (and step) to the next while the factorisation lasts: W then stands.
    if (!(s.row_columns.same_columns_as_previous_call() && s.delassus.built_direct(m)))
      s.delassus.build_direct(s.rows, model.free_index, s.row_column_scratch, &model.node_body,
                              s.row_columns.complete() ? nullptr : &s.row_columns.generations());
    per_row = true;
    return solved;
  }
  const bool first_fill = s.touched_inverse.size() == 0;
  if (first_fill) s.touched_inverse_step = s.step_count;
  approximate = s.touched_inverse.stale();
  const int solved = s.touched_inverse.require(
      touched, [&](const auto& B, auto& X, const std::vector<int>& rows, const LinearSolver::ColumnPattern* pattern) {
        solver.solve_many(B, X, &rows, pattern);
      });
  if (first_fill) s.touched_inverse_first_nodes = s.touched_inverse.size();
  s.local_node.resize(model.num_nodes);
  for (int n = 0; n < model.num_nodes; ++n) {
    const int f = model.free_index[n];
    s.local_node[n] = f >= 0 ? s.touched_inverse.local(f) : -1;
  }
  s.delassus.build(s.rows, s.local_node, s.touched_inverse);
  return solved;
}

}  // namespace

// Per element, h sum_i lambda_i curvature_i over the pending rows: the constraints' part of
// the Lagrangian Hessian (lambda is an impulse, hence one h).
void settle_curvature(const Model& model, State& s) {
  if (!s.curvature_pending) return;
  s.curvature_pending = false;
  RowTable& rows = s.curvature_rows;
  if (model.has_strain_limits && rows.size() > 0) add_strain_limit_curvatures(model, s.curvature_point, rows);
  s.curvature.assign(model.num_elements, 0.0);
  s.curvature_blocks.clear();
  for (int i = 0; i < rows.size(); ++i) {
    if (rows.element[i] < 0 || rows.lambda[i] <= 0) continue;
    const double weight = model.h * rows.lambda[i];
    s.curvature[rows.element[i]] += weight * rows.curvature[i];
    if (const int b = rows.curvature_block[i]; b >= 0) {
      if (s.curvature_blocks.empty() || s.curvature_blocks.back().first != rows.element[i])
        s.curvature_blocks.push_back({rows.element[i], Eigen::Matrix<double, 12, 12>::Zero()});
      s.curvature_blocks.back().second += weight * rows.curvature_blocks[b];
    }
  }
}

// SQP on   min_v 1/2 v^T A v - b^T v   s.t.  C(x0 + h v) >= 0   (paper 000, section 5):
// each iteration linearises the rows at x_k = x0 + h v_k and solves the QP
//   H dv = -(A v_k - b) + J^T lambda,   C_k + h J dv >= 0,   lo <= lambda <= hi
// through the LCP  W lambda + c >= 0 (eq. 23), W = J H^-1 J^T, by PGS; v_k+1 = v_k + dv.
// After solve_newton's predictor (the last step's J^T lambda added to Newton's objective)
// v* is not the model's minimiser: the first QP then starts, like later ones, from the
// model's residual at v*, and runs whatever v* meets.
// W comes from H^-1 on the touched nodes only (touched_inverse.hpp, delassus.hpp). With
// solver.delassus_reuse > 1 that H^-1 may be kept from an earlier step's factorisation:
// the LCP is then solved with that approximate W~ and c + (W - W~) lambda_0 at its warm
// start lambda_0 (W lambda_0 by one solve), whose solution, iterated over SQP iterations
// (a splitting method for the LCP), converges to the exact W's; a stalled iteration
// recomputes H^-1 before refactorising.
// H = A + sum_e curvature_e R Ke R^T holds the constraints' curvature (without it the
// iteration cycles once the limits carry large forces). H comes from the step's single
// factorisation (solve_velocity), built with the previous step's multipliers; it is
// refactorised with the current ones only when the iteration stalls. With H = A and
// nothing violated at x* the paper's LCP is not needed and the stage is skipped.
// Converged when every row meets its tolerance and the last correction moved no node
// by more than sqp_position_tolerance, or, once the corrections stop shrinking, by no more
// than sqp_stall_tolerance, or when the last QP's multipliers solve the next QP
// (sqp_kkt_stop.hpp). A step that continues constrained motion linearises its first
// QP at the start-of-step velocities rather than at v* (below, with the measurements).
// Each step is taken through a backtracking line search on an l1 merit function
// (sqp_merit.hpp), and a step that ends at the cap outside its tolerances returns its last
// iterate within them, if any: without both, the paper 001 scenes' iterates swing between
// states that each violate the limits, or drift along them, to the cap (ARCHITECTURE.md,
// "SQP globalisation").
void solve_constraints(const Model& model, LinearSolver& solver, State& s) {
  StepProfile& profile = s.profile;
  s.keep_curved_factor = false;  // until this step's SQP says otherwise (the end)
  s.step_violation = 0;
  s.step_limit_violation = 0;
  const bool constrained = has_constraints(model, s);
  // Nothing can make a row: v* ends the step, whatever the factorisation it came from (with
  // an older one the loop below would end there too, reporting "no near-active constraint").
  // Except just after the last constraint went (a grab released): with an older
  // factorisation and v* far from v0 the loop refines v* by Newton iterations on A from v0
  // (linearise_at_start), and clears what the constraints left (warm start, curvature).
  if (!constrained && (s.factor_exact || s.warm_start.empty()) && !s.impulse_predicted) {
    s.has_constraint_impulse = s.constraint_impulse_steady = false;
    skip_qp_stages(profile, "nothing to solve");
    profile.skipped[static_cast<int>(Stage::Rows)] = "scene has one body, no obstacles, no energy or strain limits";
    return;
  }
  const SolverDesc& cfg = model.solver;
  const double h = model.h;
  StepScratch& sc = s.scratch;
  const bool predicted = s.impulse_predicted;
  s.impulse_predicted = false;
  bool impulse_valid = false;
  const VecX& x0 = s.x;           // unchanged here (integrate_positions comes after)
  const VecX& v_star = s.v_free;  // the Newton step of solve_velocity (or solve_newton's result);
                                  // written only once SQP is done
  VecX& v_free = sc.v_free = v_star;  // the SQP iterate v_k

  std::vector<uint64_t>& keep = sc.keep;
  keep.clear();
  for (const auto& [key, lambda] : s.warm_start)
    if (lambda > 0) keep.push_back(key);
  int sqp = 0, pgs = 0, subspace_products = 0, refactorisations = 0, solved_columns = 0, refreshes = 0;
  bool converged = false, approximate = false;  // approximate: the last W came from a kept G
  // Moves are h |dv|_inf of the correction taken (after the line search).
  double last_move = 1e300, previous_move = 1e300;
  // Line search: the merit's weights, the last QP's step d = sc.sqp_direction from v_k =
  // sc.sqp_from, and the step length tried.
  SqpMerit merit;
  MeritStep merit_step;
  double alpha = 1, first_alpha = 1;  // the step length tried, and the first one tried
  bool searching = false, have_feasible = false;
  // The worst row at the iterate the last QP started from (0 for the first QP: below).
  double from_worst = 0;
  // The least violated iterate's worst value, while none met the tolerances (infinity: none yet).
  double least_violation = std::numeric_limits<double>::infinity();
  int backtracks = 0, stalls_accepted = 0, restored = 0, conjugate_steps = 0, restorations_accepted = 0;
  const bool restoration_on = cfg.sqp_restoration == "accept";
  // The KKT stop (sqp_kkt_stop.hpp): whether the last QP may be tested (solved with this
  // step's A, its step taken whole, its LCP to tolerance, rows without curvature), and how
  // often the test ended the step. Not with PCG (inexact solves) nor hyperelastic bodies.
  const bool kkt_stop_on = cfg.sqp_kkt_stop == "on" && !model.has_hyperelastic && solver.uses_cholmod();
  bool kkt_testable = false;
  int kkt_stops = 0;
  // Conjugate steps: whether the last QP left its direction and A times it in scratch.
  bool conjugate_ready = false;
  const bool conjugate_steps_on = cfg.sqp_acceleration == "conjugate";
  const bool shared_solves_on = cfg.sqp_solves == "shared";
  double previous_curvature = 0;
  // Sized here, not at the first step that needs them (a warm step allocates nothing).
  sc.sqp_feasible.resize(v_free.size());
  if (kkt_stop_on) {  // by the row tables' capacity: they grow only with them
    const std::size_t rows_capacity = std::max(s.rows.key.capacity(), s.curvature_rows.key.capacity());
    sc.kkt_rows.reserve(rows_capacity);
    sc.kkt_lambda.reserve(rows_capacity);
  }
  sc.sqp_previous_direction.resize(v_free.size());
  sc.sqp_previous_product.resize(v_free.size());
  // b - A v_k at the first iterate from solve_newton's residual at v* (rhs - A v*, formed
  // without a product; s.rhs then stays stage 1's): that residual itself, or, for a QP
  // linearised at v0, plus A (v* - v0).
  bool started_at_v0 = false;  // the first QP was linearised at v0 (stats)
  const auto residual_from_model = [&] {
    sc.residual = s.model_residual;
    if (!started_at_v0) return;
    sc.dv = v_star - v_free;
    multiply_step_system(model, s, sc.dv, sc.step);
    sc.residual += sc.step;
  };
  const auto rows_at_iterate = [&](int k) {
    StageTimer timer(profile, Stage::Rows);
    if (!constrained) {
      s.rows.clear();
      return s.step_violation = 0.0;
    }
    ++profile.work.row_builds;
    sc.x_iterate = x0 + h * s.v;
    // Every way out of the loop below builds the rows at the step's last iterate: this is
    // then the step's violation.
    return s.step_violation = build_rows(model, s.t + h, k, sc.x_iterate, s.v, sc.strain_cut_gaps, keep, s.attachments, s.rows,
                                         s.body_surfaces, s.energy_screen, sc, profile, s.step_limit_violation);
  };
  // v* violates something. When the previous step was constrained too, v* has left out
  // the forces that held the body (a finger pressed on a table: v* runs 0.5 m through
  // it), and the constraints linearised there are far from their solution (strain
  // limits at 20 % past instead of < 1 %, every surface vertex a contact row). The
  // start-of-step velocities already satisfy them to first order: when v* strays from
  // them by more than a contact margin, the first QP is linearised there instead (its
  // v_base stays v*; the linear model and the rows found within the margin differ, and
  // rows violated only at x* join at the next iteration). Closer than that, x* is the
  // better guess (the resting creature: one SQP iteration fewer from x*).
  // The strain rows' Jacobians, left out of every build: of the flat finger's 3-7 builds a
  // step, only those the SQP linearises at (one per QP) need them. The step's last build (its
  // rows stay in s.rows) is a line-search trial or the iterate the step ends at, so s.rows
  // keeps zero strain Jacobians after a step (no QP followed): nothing reads them then
  // (fall_asleep.cpp reads the stencils' nodes).
  const auto complete_jacobians = [&] {
    if (!model.has_strain_limits) return;
    StageTimer timer(profile, Stage::Rows);
    complete_strain_limit_jacobians(model, s.rows, &sc.strain_row_buffers);
  };
  if (model.has_strain_limits) strain_pair_cut_gaps(model, s.v_start, sc.strain_cut_gaps);  // one gate a step
  const bool linearise_at_start = !s.warm_start.empty() && strays_beyond_margin(model, s.v_start, v_star);
  int sqp_cap = IterationCaps::effective(cfg.sqp_max_iterations, s.caps.sqp);
  const bool may_extend =
      cfg.sqp_cap_extension == "once" && s.last_step_within_limits && sqp_cap == cfg.sqp_max_iterations;
  bool extended = false;
  for (int k = 0;; ++k) {
    // Rows at v* serve to stop at once when v* meets them all, which only an exact
    // factorisation may do (below), and otherwise only to keep v* as the fallback of a step
    // that ends at the SQP cap outside its tolerances: then the first rows are built at v0
    // alone (the flat finger: one strain and contact row build, 0.2-0.3 ms, fewer per step),
    // and v* is no fallback (results change only for such a step, when v* met every row).
    const bool skip_v_star = k == 0 && linearise_at_start && !s.factor_exact;
    if (skip_v_star) {
      started_at_v0 = true;
      v_free = s.v_start;
      scatter_free(model, v_free, s.v);
    }
    double worst = rows_at_iterate(k);
    // Armijo backtracking: halve the step until the merit falls by 1e-4 of the predicted
    // change, at most kBacktracks times (the last half is taken regardless). Every trial
    // point's rows are built anyway, as the next QP's linearisation. Moves below are the
    // steps taken: a QP step whose halvings all fail moves 1/32 of itself, and within the
    // tolerances that ends the step (the merit found nothing better along it).
    constexpr int kBacktracks = 5;
    // A first trial that meets every row's tolerance and moves no node further than
    // sqp_position_tolerance ends the step as converged whatever the merit says: at that
    // scale the merit's change is round-off and second-order terms of the rows, and the
    // halvings (a row build each) only shorten a step the test below accepts anyway (the
    // settled side-pressed finger: 5 failed halvings on most steps, 1/32 of the QP's
    // step taken).
    // (last_move is still the QP step's own length h |d|, as the test judges it; a
    // conjugate step's first trial may be up to twice it, and must be within it too.)
    if (searching && worst <= 1 && std::max(1.0, alpha) * last_move <= cfg.sqp_position_tolerance)
      searching = false;
    // With solver.sqp_restoration "accept" (not the default: it did not save time), a
    // first trial that brings an iterate past a tolerance within every one is taken whatever
    // the merit says (a filter's acceptance: it is strictly less violated in the measure the
    // tolerances use). The l1 merit sums every row's violation: where a QP step brings the
    // worst row from past its tolerance to well within it, many rows may each end a little
    // violated, still within tolerance, and the sum rise above the few rows' before. Halving
    // then walks back towards the violated iterate, and the last half, taken regardless,
    // ends past the tolerance again (the flat finger: full steps at 0.25-0.31 of the
    // tolerance rejected at five QPs in a row, each ending at 1.2-1.3 of it, to the cap).
    // Not for the first QP: its start's worst counts any predicted penetration as 2.
    // Counted only where the merit would have rejected it.
    if (searching && restoration_on && worst <= 1 && from_worst > 1) {
      searching = false;
      if (merit_step.change(alpha, merit.penalty(s.rows, h)) > 1e-4 * alpha * merit_step.predicted_change())
        ++restorations_accepted;
    }
    for (int back = 0; searching; ++back) {
      const double change = merit_step.change(alpha, merit.penalty(s.rows, h));
      if (change <= 1e-4 * alpha * merit_step.predicted_change() || back == kBacktracks) break;
      alpha *= 0.5;
      v_free = sc.sqp_from + alpha * sc.sqp_direction;
      scatter_free(model, v_free, s.v);
      worst = rows_at_iterate(k);
      ++backtracks;
    }
    if (searching) last_move = std::min(1.0, alpha / first_alpha) * h * sc.sqp_direction.lpNorm<Eigen::Infinity>();
    searching = false;
    // v* meets every row: it ends the step with an exact factorisation, and with an older one
    // when there are no rows at all (the QP from v* would be the step d = 0). Never after the
    // Newton predictor: v* holds the last step's constraint force, which only a QP may keep.
    const bool no_rows = s.rows.size() == 0;
    // Whether v_k is taken as the quadratic model's minimiser (v*, residual r = 0, or what
    // Newton left of its gradient when solve_newton kept it, within a tenth of the step's
    // scale, left to the next iterations): the first QP's, unless Newton took the
    // predictor's force, which leaves r = -J^T lambda_0 there. Every other QP starts from the
    // model's Newton step H^-1 r at v_k.
    const bool at_minimiser = k == 0 && !predicted;
    if (at_minimiser && (s.factor_exact ? no_rows || worst <= 1 : no_rows && !skip_v_star)) break;
    if (k > 0 && worst <= 1 && last_move <= cfg.sqp_position_tolerance) {
      converged = true;
      break;
    }
    // The last QP's multipliers already solve the next QP (no halving of its step: alpha is
    // still 1): the iterate is a KKT point, and that QP would only confirm it.
    if (k > 0 && kkt_testable && alpha == 1 && worst <= 1 &&
        last_multipliers_solve(s.curvature_rows, s.rows, h, cfg, sc.kkt_rows, sc.kkt_lambda)) {
      converged = true;
      ++kkt_stops;
      break;
    }
    // Within tolerance, corrections that no longer shrink are rows switching on and off at
    // their limits: the flat finger's 4-7 strain rows, moves of 1.1-1.6e-5 m to the cap.
    // Accepted up to sqp_stall_tolerance; above it (the fig. 2 beam's 1e-4-1e-3 m), the
    // iterate is still far from the solution and taking it made that beam blow up.
    if (k >= 2 && worst <= 1 && last_move > 0.5 * previous_move && last_move <= cfg.sqp_stall_tolerance) {
      converged = true;
      ++stalls_accepted;
      break;
    }
    // The fallback: the last iterate within the tolerances, or, while none has been, the
    // least violated QP solution (not v*, which leaves the constraints out).
    if (worst <= 1 && !skip_v_star && (k > 0 || at_minimiser)) {  // v0, v* with a predictor: no QP solution
      sc.sqp_feasible = v_free;
      have_feasible = true;
    } else if (k > 0 && !have_feasible && worst < least_violation) {
      sc.sqp_feasible = v_free;
      least_violation = worst;
    }
    if (k == sqp_cap && (k > 0 || at_minimiser)) {
      // A step after one that ended within every limit's tolerance, reaching the cap outside them
      // with none of its iterates within them, goes on for as many iterations again, once: an
      // impact that one more handful of QPs resolves (paper 001's tip-pressed finger, its load
      // scaled by 1 + 3e-14, met the tip at step 7 203 tolerances past its limits and came within
      // them at QP 21-25, where the cap of 20 returned its least violated iterate, 1.02 tolerances
      // past). Not at a budget's lower cap (a budget trades accuracy; its guard redoes steps left
      // past budget_violation_limit), nor after a step that ended outside its limits (paper 001's
      // orthogonal projection cannot meet them: its steps would double their QPs for nothing).
      if (may_extend && !extended && s.step_limit_violation > 1 && !have_feasible) {
        extended = true;
        sqp_cap += cfg.sqp_max_iterations;
      } else {
        // The merit weighs small violations lightly (and does not fall at every iteration: a
        // last half is taken regardless, a non-descent step whole), so the last iterate may be
        // over a tolerance that an earlier one met (the tip-pressed finger), or, where the
        // limits cannot all be met (paper 001's orthogonal projection: [1, 1] on two axes),
        // far more violated than an earlier one: taken, that one ran away within 3 steps
        // (worst strain violation 0.02 -> 2.1 -> 57 -> 2100, the column 52 m down).
        if (worst > 1 && (have_feasible || least_violation < worst)) {  // never true for worst = NaN
          v_free = sc.sqp_feasible;
          scatter_free(model, v_free, s.v);
          rows_at_iterate(k);
          ++restored;
        }
        break;
      }
    }
    if (k == 0 && linearise_at_start && s.factor_exact) {  // v* violates something: as above
      started_at_v0 = true;
      v_free = s.v_start;
      scatter_free(model, v_free, s.v);
      rows_at_iterate(k);
    }
    complete_jacobians();  // this iterate's rows are linearised at
    const int m = s.rows.size();
    // No row with curvature (no energy or strain row): the KKT stop's extra sweep and test,
    // the conjugate steps and the merit's first trial depend on it.
    const bool rows_linear = rows_without_curvature(s.rows);
    ++sqp;
    impulse_valid = false;
    for (int i = 0; i < m; ++i) s.rows.lambda[i] = warm_lambda(s.warm_start, s.rows.key[i]);

    VecX& v_base = sc.v_base = at_minimiser ? v_star : v_free;
    {
      StageTimer timer(profile, Stage::SqpFactorize);
      // Stalled: a kept H^-1 (delassus_reuse) converges too slowly, recompute it; else the
      // stale curvature does, refactorise with the current one.
      const bool stalled = k >= 2 && last_move > 0.5 * previous_move;
      if (stalled && approximate && s.touched_inverse.stale()) {
        s.touched_inverse.reset(model.num_free);
        ++refreshes;
      } else if (stalled) {
        if (!factorize_step_system(model, solver, s, false)) break;
        s.factor_exact = !s.factor_curved;
        s.factor_unmoved = false;
        conjugate_ready = false;  // the last direction came from the old H
        ++refactorisations;
      }
    }
    StageTimer solve_timer(profile, Stage::SqpSolve);
    // With the rows' columns Y = H^-1 J^T at hand, J H^-1 r = Y^T r needs no solve, and the
    // Newton step and the correction share one: v_k+1 = v_k + H^-1 (r + J^T lambda). Taken
    // when the m dot products cost less than the solve they save (two passes over L): the
    // creature's 96-99 rows of 1950 DOFs against a supernodal factor of 222k entries.
    // Otherwise the columns serve W alone and need to be right on the rows' stencils only.
    const bool columns_cheaper =
        shared_solves_on && static_cast<double>(m) * static_cast<double>(v_free.size()) < 2.0 * solver.factor_entries();
    bool per_row = false;
    if (m > 0) solved_columns += factor_delassus(model, solver, s, approximate, per_row, columns_cheaper);
    const bool whole_columns = per_row && columns_cheaper && s.row_columns.complete();
    const Eigen::Map<const VecX> lambda0(s.rows.lambda.data(), m);
    // The first QP after the Newton predictor: when the predictor's force is J^T lambda_0 of
    // these very rows, bit for bit (contacts on a plane, held at rest), r = -J^T lambda_0 - e
    // at Newton's result, e what Newton left of its gradient when solve_newton's model keeps
    // it (within a tenth of the step's scale), else 0, so
    // v = v_k + H^-1 (r + J^T lambda) = v_k + H^-1 J^T (lambda - lambda_0) - H^-1 e and the LCP
    // is C/h + W (lambda - lambda_0) >= 0 (e left out of it): c = C/h - W lambda_0 from the W
    // PGS uses, no solve and no W lambda_0 correction (an approximate W's cancels), then one
    // solve of r + J^T lambda, or, with whole columns, Y (lambda - lambda_0) and none (e left
    // to a later iteration's residual). Otherwise the first QP would take one or two solves
    // more than without the predictor (cube_20 at rest: one QP a step either way).
    bool predicted_match = false;
    if (k == 0 && predicted && m > 0) {
      apply_jacobian_transpose(model, s.rows, sc.impulse);  // lambda_0: the warm start, set above
      predicted_match = sc.impulse == sc.newton_predicted_impulse;
    }
    const bool one_solve = !at_minimiser && whole_columns && !predicted_match;
    // With an approximate W (a kept G), W lambda_0 costs a solve, and so does the Newton
    // step H^-1 r; the LCP needs only J H^-1 (r + J^T lambda_0) of them, one solve, and
    // v_k+1 = v_k + H^-1 (r + J^T lambda) follows the LCP: two solves per iteration, not three.
    const bool correct = m > 0 && approximate && !lambda0.isZero(0) && !predicted_match;
    const bool fused = !at_minimiser && !one_solve && correct && shared_solves_on;
    if (k == 0 && !at_minimiser) {  // r at Newton's result (later iterations update it below)
      if (s.model_residual_known) {
        residual_from_model();
      } else {
        assert(!model.has_hyperelastic);  // Newton leaves s.rhs as stage 1's b: r comes from it alone
        multiply_step_system(model, s, v_free, sc.residual);
        sc.residual = s.rhs - sc.residual;
      }
    }
    if (!at_minimiser) {
      // b - A v_k from b - A v_k-1, as v_k = v_k-1 + alpha d and the merit kept A d: one
      // product with A per iteration fewer (the creature: 1950 DOFs, 108k entries, 0.035 ms each).
      if (k > 0) sc.residual.noalias() -= alpha * sc.sqp_product;
      if (!one_solve && !fused && !predicted_match) {
        sc.step.setZero(v_free.size());
        solver.solve(sc.residual, sc.step, factor_use(s));
        v_base += sc.step;
      }
    }
    VecX& v_next = sc.v_next = v_base;
    bool lcp_converged = true;
    if (m > 0) {
      // c, J (v_base - v_k), weights; with an approximate W: W lambda_0, W~ lambda_0
      Eigen::Map<MatX> per_row_values = sc.per_row.view(m, 6);
      auto c = per_row_values.col(0), jdv = per_row_values.col(1), weights = per_row_values.col(2);
      auto exact_w = per_row_values.col(3), approximate_w = per_row_values.col(4), start_lambda = per_row_values.col(5);
      if (predicted_match) start_lambda = lambda0;  // PGS overwrites the rows' lambda
      if (correct) {  // fused: exact_w = J H^-1 (r + J^T lambda_0), which holds J (v_base - v_k) too
        if (!(k == 0 && predicted)) apply_jacobian_transpose(model, s.rows, sc.impulse);  // else there already
        if (fused) sc.impulse += sc.residual;
        sc.correction.setZero(v_free.size());
        solver.solve(sc.impulse, sc.correction, factor_use(s));
        exact_w.setZero();
        add_jacobian_times(model, s.rows, sc.correction, exact_w);
        s.delassus.multiply(lambda0, approximate_w);
      }
      if (one_solve) {
        // m dot products of length n (the creature: 72 x 1950), each summed by one task:
        // the same sums for any thread count.
        const Eigen::Index n = v_free.size();
        tbb::parallel_for(tbb::blocked_range<int>(0, m, 8), [&](const tbb::blocked_range<int>& range) {
          for (int i = range.begin(); i < range.end(); ++i)
            jdv[i] = Eigen::Map<const VecX>(s.row_column_scratch[i], n).dot(sc.residual);
        });
      }
      solve_timer.stop();
      {
        StageTimer pgs_timer(profile, Stage::Pgs);
        // C_k + h J (v - v_k) >= 0 with v = v_base + H^-1 J^T lambda.
        const bool active_set = !s.delassus.dense() && cfg.pgs_sweeps == "active_set";
        // After the predictor c = C/h - W lambda_0; sweeping every row, PGS takes it as C/h
        // with its products of lambda - lambda_0 (solve_pgs's offset): no product at its
        // start from lambda_0, where w = C/h, and none for W lambda_0 (cube_20 at rest: two
        // passes over a dense 663 x 663 W fewer, 3.5 MB each, a step).
        const bool offset_form = predicted_match && !active_set;
        if (offset_form) {
          jdv.setZero();
        } else if (predicted_match) {
          s.delassus.multiply(lambda0, jdv);
          jdv = -jdv;
        } else if (fused) {
          jdv.setZero();
        } else if (!one_solve) {
          sc.dv = v_base - v_free;
          jdv.setZero();
          add_jacobian_times(model, s.rows, sc.dv, jdv);
        }
        c = Eigen::Map<const VecX>(s.rows.value.data(), m) / h + jdv;
        if (correct) c += exact_w - approximate_w;
        residual_weights(cfg, h, s.rows, weights);
        const int pgs_cap = IterationCaps::effective(cfg.pgs_max_iterations, s.caps.pgs);
        PgsResult result =
            active_set ? s.active_set_pgs.solve(s.delassus, c, weights, s.rows, pgs_cap, cfg.pgs_tolerance,
                                                cfg.pgs_subspace_interval)
                       : solve_pgs(s.delassus, c, weights, s.rows, pgs_cap, cfg.pgs_tolerance, cfg.pgs_subspace_interval,
                                   offset_form ? start_lambda.data() : nullptr);
        lcp_converged = result.residual <= cfg.pgs_tolerance;
        // A QP the KKT stop may end the step after (sqp_kkt_stop.hpp) takes the sweep the
        // confirming QP would have made from its multipliers: without it a box resting on a
        // plane (sleep off) settled a sweep a step slower, kept rotations moving above 1e-12
        // for 160 steps instead of 45 and refactorised on each of them.
        if (lcp_converged && kkt_stop_on && s.factor_exact && result.iterations < pgs_cap && rows_linear)
          result.iterations +=
              solve_pgs(s.delassus, c, weights, s.rows, 1, 0.0, 0, offset_form ? start_lambda.data() : nullptr).iterations;
        pgs += result.iterations;
        subspace_products += result.subspace_products;
      }
      StageTimer timer(profile, Stage::SqpSolve);
      apply_jacobian_transpose(model, s.rows, sc.impulse);
      impulse_valid = true;
      sc.correction.setZero(v_free.size());
      if (one_solve || fused || (predicted_match && !whole_columns)) {
        sc.dv = sc.residual + sc.impulse;
        solver.solve(sc.dv, sc.correction, factor_use(s));
      } else if (whole_columns) {
        // H^-1 J^T lambda = Y lambda from the rows' own columns, no solve (the first QP of
        // a step, Y (lambda - lambda_0) after the Newton predictor; later ones fold it into
        // the Newton step's solve above). Each entry sums the
        // columns in row order, by one task, in chunks that depend on n alone (the simple
        // partitioner): the same sums, and the same vectorised and scalar parts, for any
        // thread count.
        const Eigen::Index n = v_free.size();
        tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 256), [&](const tbb::blocked_range<Eigen::Index>& range) {
          const Eigen::Index first = range.begin(), count = range.end() - range.begin();
          for (int i = 0; i < m; ++i)
            if (const double lambda = s.rows.lambda[i] - (predicted_match ? start_lambda[i] : 0.0); lambda != 0)
              sc.correction.segment(first, count) += lambda * Eigen::Map<const VecX>(s.row_column_scratch[i] + first, count);
        }, tbb::simple_partitioner());
      } else {
        solver.solve(sc.impulse, sc.correction, factor_use(s));
      }
      v_next += sc.correction;
    }
    // The merit along the step d from v_k (whose rows are s.rows, their values unchanged by
    // the QP), with the weights raised for this QP's multipliers. Not a predicted descent
    // (an inexact LCP; an energy limit's Jacobian without dR/dx; the first QP from v* when
    // H is not A, as v_base = v* is then not H's Newton step): the step is taken whole.
    // After the Newton predictor the first QP is treated like later ones: its residual is
    // b - A v_k at v_k (computed above), not zero.
    // To the end of the iteration: the merit's products with A (element by element when the
    // matrix is not assembled: 0.06 ms a QP on the creature) and the bookkeeping.
    solve_timer.stop();  // already, unless there were no rows
    StageTimer merit_timer(profile, Stage::SqpMerit);
    merit.raise_weights(s.rows);
    sc.sqp_direction = v_next - v_free;
    if (k == 0 && started_at_v0 && !model.has_hyperelastic) {
      // b - A v0 is stage 1's (assemble_system's element pass): one column fewer.
      multiply_step_system(model, s, sc.sqp_direction, sc.sqp_product);
      sc.residual = s.start_residual;
    } else if (at_minimiser && s.model_residual_known) {
      multiply_step_system(model, s, sc.sqp_direction, sc.sqp_product);
      residual_from_model();
    } else if (at_minimiser) {  // else sc.residual = b - A v_k already (above)
      assert(!model.has_hyperelastic);  // as above
      multiply_step_system(model, s, sc.sqp_direction, sc.sqp_product, v_free, sc.residual);
      sc.residual = s.rhs - sc.residual;
    } else {
      multiply_step_system(model, s, sc.sqp_direction, sc.sqp_product);
    }
    // With an exact factorisation and rows without curvature the QP's step is already the
    // Lagrangian's minimiser (step length 1, nothing to conjugate against).
    const bool accelerate = conjugate_steps_on && !s.factor_exact;
    // d's slopes: of f, (A v_k - b)^T d, and of the Lagrangian f - lambda^T C, less
    // (J^T lambda)^T d (sc.impulse is J^T lambda).
    const auto slopes = [&](double& objective, double& lagrangian) {
      objective = -sc.residual.dot(sc.sqp_direction);
      lagrangian = objective - (m > 0 ? sc.impulse.dot(sc.sqp_direction) : 0.0);
    };
    double objective_slope, lagrangian_slope;
    slopes(objective_slope, lagrangian_slope);
    merit_step.curvature = sc.sqp_direction.dot(sc.sqp_product);
    merit_step.slope = objective_slope - friction_work(model, s.rows, sc.sqp_direction);
    merit_step.penalty_from = merit.penalty(s.rows, h);
    merit_step.penalty_to = 0;
    searching = merit_step.predicted_change() < 0;
    // Only a predicted descent is damped or conjugated: other steps are taken whole, at 1.
    alpha = accelerate && searching ? MeritStep::first_trial(rows_linear, lagrangian_slope, merit_step.curvature) : 1.0;
    bool conjugated = false;
    if (accelerate && searching && conjugate_ready && rows_linear && same_rows_as_last_qp(s.rows, s.warm_start)) {
      // An earlier step's factorisation makes the QP steps a stationary iteration on the
      // true QP (preconditioned by H), which converges linearly; with rows that stay the
      // same and carry no curvature, the Lagrangian is a quadratic in A, and making the
      // step A-conjugate to the last one turns that iteration into conjugate gradients,
      // as PCG does with H as its preconditioner. Kept only when it is a predicted descent
      // and the step to the minimiser along it is in (0, 2), like the plain step.
      const double beta = -sc.sqp_product.dot(sc.sqp_previous_direction) / previous_curvature;
      sc.sqp_previous_direction = sc.sqp_direction + beta * sc.sqp_previous_direction;
      sc.sqp_previous_product = sc.sqp_product + beta * sc.sqp_previous_product;
      sc.sqp_direction.swap(sc.sqp_previous_direction);
      sc.sqp_product.swap(sc.sqp_previous_product);
      double conjugate_objective, conjugate_lagrangian;
      slopes(conjugate_objective, conjugate_lagrangian);
      const double curvature = sc.sqp_direction.dot(sc.sqp_product);
      const double slope = conjugate_objective - friction_work(model, s.rows, sc.sqp_direction);
      // p need not meet the linearised rows as the QP's step does: their penalty at
      // v_k + p enters its predicted change.
      auto jp = sc.per_row.view(m, 6).col(1);
      jp.setZero();
      add_jacobian_times(model, s.rows, sc.sqp_direction, jp);
      const double penalty_to = merit.penalty_along(s.rows, jp, h);
      const double minimiser = curvature > 0 ? -conjugate_lagrangian / curvature : -1;
      if (slope + penalty_to - merit_step.penalty_from < 0 && minimiser > 0 && minimiser < 2) {
        conjugated = true;
        merit_step.slope = slope;
        merit_step.curvature = curvature;
        merit_step.penalty_to = penalty_to;
        alpha = minimiser;
      } else {  // back to the QP's own step
        sc.sqp_direction.swap(sc.sqp_previous_direction);
        sc.sqp_product.swap(sc.sqp_previous_product);
      }
    }
    // This direction and A times it, for the next QP's conjugate step.
    conjugate_ready = rows_linear && merit_step.curvature > 0;
    if (conjugate_ready) {
      sc.sqp_previous_direction = sc.sqp_direction;
      sc.sqp_previous_product = sc.sqp_product;
      previous_curvature = merit_step.curvature;
    }
    if (conjugated) ++conjugate_steps;
    // rows_linear also keeps strain rows out: their Jacobians are deferred (zero) in s.rows
    // at the test, and would compare equal to nothing meaningful.
    kkt_testable = kkt_stop_on && s.factor_exact && rows_linear && lcp_converged && alpha == 1 && !conjugated;
    sc.sqp_from = v_free;
    from_worst = k > 0 ? worst : 0.0;
    previous_move = last_move;
    // The convergence and stall tests judge the step's own length (h |d|, at the first
    // trial's scale), not the damping the minimiser chose; halvings still shorten it.
    first_alpha = alpha;
    last_move = h * sc.sqp_direction.lpNorm<Eigen::Infinity>();
    if (alpha == 1 && !conjugated) v_free = v_next;
    else v_free = sc.sqp_from + alpha * sc.sqp_direction;
    scatter_free(model, v_free, s.v);

    // Rows stay for the rest of the step once active, so the active set only grows.
    s.warm_start.clear();
    for (int i = 0; i < m; ++i) {
      s.warm_start.emplace_back(s.rows.key[i], s.rows.lambda[i]);
      keep.push_back(s.rows.key[i]);
    }
    std::sort(s.warm_start.begin(), s.warm_start.end());
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    // These rows, at their point, for the next factorisation's curvature (if any): swapped,
    // not copied, as every way out of this loop first rebuilds s.rows (rows_at_iterate).
    std::swap(s.curvature_rows, s.rows);
    // The count of rows built stays with s.rows (StepWork::rows: it went negative when it
    // travelled with the tables).
    std::swap(s.curvature_rows.appended, s.rows.appended);
    s.curvature_point = sc.x_iterate;
    s.curvature_pending = true;
  }
  s.v_free = v_free;
  // The next Newton solve's predictor (solve_newton.cpp): kept in scenes with a Newton solve
  // (whatever solver.newton_predictor, so that a state carries it to a world that uses it),
  // and not when zero (rows within the margin carrying no force), which would only cost the
  // next step the end at v* that an exact factorisation allows. Used only while steady: it
  // changed by at most kSteadyImpulse (relative) from the step before's. Through an impact
  // the last impulse is a poor guess of the next, and the SQP's iterations from it stalled
  // and refactorised (cube_20's landing, frames 0-29: 2 refactorisations and 3,795 column
  // solves against none and 2,349 without the predictor; with the rule none and 2,349, and
  // the bunny_5 drop's 65 frames 3 -> 1 refactorisations, 192 -> 118 QPs).
  constexpr double kSteadyImpulse = 0.1;
  const bool had_impulse = s.has_constraint_impulse;
  // Not after a QP with energy or strain rows: their J^T lambda, a fixed force in Newton's
  // objective, no longer balances once the elements turn and stretch under it, and the
  // side-pressed SNH finger (paper 001, fig. 3) went from steps predicted at the steady 200 N
  // press to 12 Newton iterations, ~3,900 strain rows and the SQP cap (0.02-0.24 past its
  // limits, 1.5 mm into the table, 19-34 steps retried); without: within 1e-3 and 2.2e-5 m,
  // none capped or retried. The contacts' part alone, predicted without the limits' that
  // held the body against it, was worse (the flat-pressed finger 0.43 past its limits).
  const RowTable& last_qp = s.curvature_rows;  // the last QP's rows (swapped in above)
  const bool limit_rows = last_qp.count(RowKind::Energy) + last_qp.count(RowKind::Strain) > 0;
  s.has_constraint_impulse = impulse_valid && model.has_hyperelastic && !sc.impulse.isZero(0) && !limit_rows;
  s.constraint_impulse_steady = false;
  if (s.has_constraint_impulse) {
    double change2 = 0, size2 = 0;
    for (int n = 0; n < model.num_nodes; ++n) {
      const int f = model.free_index[n];
      const Vec3 next = f >= 0 ? Vec3(sc.impulse.segment<3>(3 * f)) : Vec3::Zero();
      change2 += (next - s.constraint_impulse.segment<3>(3 * n)).squaredNorm();
      size2 += next.squaredNorm();
      s.constraint_impulse.segment<3>(3 * n) = next;
    }
    s.constraint_impulse_steady = had_impulse && change2 <= kSteadyImpulse * kSteadyImpulse * size2;
  }
  if (sqp == 0) {
    skip_qp_stages(profile, s.rows.size() ? "no row violated" : "no near-active constraint");
    s.warm_start.clear();
    s.curvature.clear();
    s.curvature_blocks.clear();
    s.curvature_pending = false;
  }
  for (int kind = 0; kind < kRowKindCount; ++kind)
    if (const int n = s.rows.count(static_cast<RowKind>(kind))) profile.rows[row_kind_name(static_cast<RowKind>(kind))] = n;
  profile.iterations["sqp"] += sqp;
  // What a curved factorisation is worth to the next step (solve_velocity.cpp): the SQP
  // iterations of the step that made it are the yardstick, and a step that needs more, or
  // refactorises, or ends outside its tolerances, has the next one factorise afresh. A step
  // that accepted a stall may keep it: the flat-pressed finger stalls on most steps (rows
  // switching at their limits) and kept 7 instead of 21 of 90 factorisations without it,
  // its median step 3.3-3.8 -> 4.3 ms, at no gain in accuracy (docs/work_precision.md).
  // An extended step is no yardstick: its factorisation needed more than the cap.
  if (s.factor_age == 0) s.factor_sqp = refactorisations || extended ? -1 : sqp;
  s.keep_curved_factor =
      converged && refactorisations == 0 && !extended && sqp > 0 && sqp <= s.factor_sqp;
  profile.iterations["pgs"] += pgs;
  if (refactorisations) profile.iterations["sqp_refactorisations"] += refactorisations;
  // Reported whenever PGS ran with subspace steps on, 0 included: a name first met in a
  // warm step would allocate there (profile_map.hpp).
  if (sqp > 0 && cfg.pgs_subspace_interval > 0) profile.iterations["pgs_subspace_products"] += subspace_products;
  if (solved_columns) profile.iterations["solved_columns"] += solved_columns;
  if (refreshes) profile.iterations["delassus_refreshes"] += refreshes;
  // Reported on every constrained step, 0 included: a name first met in a warm step would
  // allocate (profile_map.hpp).
  profile.iterations["sqp_backtracks"] += backtracks;
  profile.iterations["sqp_stalls_accepted"] += stalls_accepted;
  profile.iterations["sqp_restorations_accepted"] += restorations_accepted;
  profile.iterations["sqp_kkt_stops"] += kkt_stops;
  profile.iterations["sqp_restored"] += restored;
  profile.iterations["sqp_extended"] += extended ? 1 : 0;
  profile.iterations["sqp_conjugate_steps"] += conjugate_steps;
  profile.iterations["sqp_linearised_at_start"] += started_at_v0 ? 1 : 0;
  // Not converged with a kept H^-1: the next factorisation recomputes it.
  if (sqp > 0 && !converged && s.touched_inverse.stale()) s.touched_inverse_step = s.step_count - cfg.delassus_reuse;
}

}  // namespace sinew
