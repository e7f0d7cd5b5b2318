#include "engine/world.hpp"

#include <chrono>
#include <cstring>

#include "engine/sleep/sleep.hpp"
#include "engine/step/stages.hpp"

namespace sinew {

World::World(Model model, const std::vector<Vec3>& initial_velocity)
    : m_model(std::move(model)), m_solver(m_model.solver) {
  State& s = m_state;
  s.x = m_model.rest_x;
  s.v = VecX::Zero(3 * m_model.num_nodes);
  for (int n = 0; n < m_model.num_nodes; ++n) {
    const int b = m_model.node_body[n];
    if (m_model.free_index[n] >= 0 && b < static_cast<int>(initial_velocity.size()))
      s.v.segment<3>(3 * n) = initial_velocity[b];
  }
  s.R.assign(m_model.num_elements, Mat3::Identity());
  s.force = VecX::Zero(3 * m_model.num_nodes);
  s.external_force = VecX::Zero(3 * m_model.num_nodes);
  s.system = m_model.pattern.matrix;
  s.rhs = VecX::Zero(3 * m_model.num_free);
  s.v_free = VecX::Zero(3 * m_model.num_free);
  // Sized once: a step where contact begins allocates nothing for the Newton predictor.
  s.constraint_impulse = VecX::Zero(3 * m_model.num_nodes);
  s.scratch.newton_predicted_impulse = VecX::Zero(3 * m_model.num_free);
  // No factorisation yet: the first step makes one whatever step_count a caller carries
  // over (ui's LiveScene rebuilds keep it), never reusing one it does not have.
  s.factor_age = m_model.solver.refactor_interval;
  s.keep_curved_factor = false;
  s.factor_rotations.clear();
  s.surface.resize(m_model.bodies.size());
  update_surfaces(m_model, s);
  const size_t bodies = m_model.bodies.size();
  s.sleep.asleep.assign(bodies, 0);
  s.sleep.quiet_steps.assign(bodies, 0);
  s.sleep.island.assign(bodies, -1);
  s.sleep.bounds.assign(bodies, Aabb{});
}

void World::apply_sleeping_set() {
  State& s = m_state;
  s.sleep.changed = false;
  if (s.sleep.count() == 0) m_frozen.reset();
  else m_frozen = std::make_unique<Model>(freeze_sleeping_bodies(m_model, s.sleep.asleep));
  const Model& model = stage_model();
  s.system = model.pattern.matrix;
  s.system_assembled = false;
  s.rhs = VecX::Zero(3 * model.num_free);
  s.v_free = VecX::Zero(3 * model.num_free);
  s.scratch.newton_predicted_impulse = VecX::Zero(3 * model.num_free);
  s.factor_age = m_model.solver.refactor_interval;  // no reuse of a factorisation of the old pattern
  s.keep_curved_factor = false;
  s.factor_rotations.clear();
  s.touched_inverse.reset(model.num_free);
  s.row_columns.reset();
  // Newton's kept matrices are of the old pattern, and its start_from_A0 writes values alone
  // into a matrix of the step's size and entry count: dropped, so the next Newton step copies
  // the new pattern whole (two awake sets of equal size and count would otherwise mix).
  s.scratch.newton_A0 = SparseMatrix();
  s.scratch.newton_H = SparseMatrix();
  s.kept_tet_hessians.clear();  // scattered into the old pattern's values
  m_solver.reset_pattern();
}

void World::rest_step() {
  State& s = m_state;
  // s.rows keeps the rows of the last step that ran: those the sleepers rest on.
  for (std::string& reason : s.profile.skipped) reason = "all bodies asleep";
  s.profile.iterations["sleeping_bodies"] = s.sleep.count();
  s.t += m_model.h;
  ++s.step_count;
}

// A failed attempt is rolled back (attempt_step) and retried, deterministically: first
// afresh (a new factorisation, or the one held if it is of the very same matrix, bit for
// bit (Newton, holds_factor_of); no warm start, no constraint curvature: what a step carries
// over from the last one is the usual suspect), then as 2 and then 4 sub-steps of h/2 and
// h/4 (each sub-step afresh too). t and step_count advance as for one step of h.
bool World::step() {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  State& s = m_state;
  if (attempt_step()) return true;
  // The profile describes the attempt that stood; the step's time counts the ones rolled
  // back before it too, apart.
  const auto time_whole_step = [&] {
    const double own_ms = s.profile.step_ms;
    s.profile.step_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    s.profile.rolled_back_ms = s.profile.step_ms - own_ms;
  };
  // Retries run at the scene's caps: the budget's may be what made the step fail.
  const IterationCaps caps = s.caps;
  s.caps = {};
  if (m_budget_guard_tripped) {
    // Left far outside a tolerance by the budget's caps: the same step at the scene's, from
    // the multipliers the capped attempt reached (a retry afresh took the pressed finger
    // ~200 ms a step) but with the factorisation decision, the curvature to settle and the
    // constraint impulse of before it; the retries below if that fails too.
    restore_before_capped_attempt();
    const bool ok = attempt_step();
    s.caps = caps;
    if (ok) {
      ++s.profile.iterations["budget_guard_retries"];
      time_whole_step();
      return true;
    }
    s.caps = {};
  }
  const double t0 = s.t, h = m_model.h;
  const long count0 = s.step_count;
  const VecX& x0 = s.scratch.step_x0 = s.x;
  const VecX& v0 = s.scratch.step_v0 = s.v;
  const bool within0 = s.last_step_within_limits;  // a sub-step accepted before a failed one set it
  int retries = 1;
  bool ok = false;
  int substeps_used = 1;
  for (const int substeps : {1, 2, 4}) {
    set_step_size(h / substeps);
    ok = true;
    for (int k = 0; k < substeps && ok; ++k) {
      forget_previous_step();
      ok = attempt_step();
    }
    if (ok) {
      substeps_used = substeps;
      break;
    }
    ++retries;
    s.x = x0, s.v = v0, s.t = t0, s.step_count = count0;
    s.last_step_within_limits = within0;
  }
  set_step_size(h);
  s.caps = caps;
  if (ok) {
    s.t = t0 + h;
    s.step_count = count0 + 1;
    // The last factorisation is of the system for h / substeps: the next step must not reuse
    // it (refactor_interval > 1), nor H^-1 from it (delassus_reuse > 1).
    if (substeps_used > 1) {
      s.factor_age = m_model.solver.refactor_interval;
      s.keep_curved_factor = false;
      s.factor_rotations.clear();
      s.touched_inverse.reset(stage_model().num_free);
      s.has_constraint_impulse = s.constraint_impulse_steady = false;  // an impulse of a sub-step, h / substeps
    }
  } else {
    forget_previous_step();
  }
  s.profile.finite = ok;
  s.profile.iterations["step_retries"] = retries;
  time_whole_step();
  return ok;
}

void World::set_step_size(double h) {
  m_model.h = h;
  if (m_frozen) m_frozen->h = h;
}

namespace {

// What a capped attempt changes that its redo at the scene's caps must not start from: the
// factorisation's age and the rule's yardstick (so that the redo decides as the attempt did),
// the curvature settled (an SQP refactorisation of the attempt would change it) and pending
// from the last step's rows (the attempt's own are of an iterate more than
// budget_violation_limit tolerances off), and the constraint impulse (Newton's predictor).
// One list for both directions, State -> kept copy and back (the same member names);
// copied into kept storage, so no allocation once warm.
template <typename From, typename To>
void copy_capped_attempt_start(const From& from, To& to) {
  to.factor_age = from.factor_age;
  to.newton_factor_spent = from.newton_factor_spent;
  to.factor_sqp = from.factor_sqp;
  to.keep_curved_factor = from.keep_curved_factor;
  to.curvature_pending = from.curvature_pending;
  to.curvature = from.curvature;
  to.curvature_blocks = from.curvature_blocks;
  if (from.curvature_pending) {
    to.curvature_rows = from.curvature_rows;
    to.curvature_point = from.curvature_point;
  }
  to.has_constraint_impulse = from.has_constraint_impulse;
  to.constraint_impulse_steady = from.constraint_impulse_steady;
  to.constraint_impulse = from.constraint_impulse;
}

}  // namespace

void World::save_before_capped_attempt() { copy_capped_attempt_start(m_state, m_capped_start); }

void World::restore_before_capped_attempt() { copy_capped_attempt_start(m_capped_start, m_state); }

void World::forget_previous_step() {
  State& s = m_state;
  s.factor_age = m_model.solver.refactor_interval;
  s.keep_curved_factor = false;
  s.factor_rotations.clear();
  s.touched_inverse.reset(stage_model().num_free);  // H^-1 kept from earlier steps (delassus_reuse)
  s.kept_tet_hessians.clear();  // a failed attempt's blocks may be of non-finite positions
  s.warm_start.clear();
  s.has_constraint_impulse = s.constraint_impulse_steady = false;
  s.impulse_predicted = false;
  s.curvature.clear();
  s.curvature_blocks.clear();
  s.curvature_pending = false;
}

bool World::attempt_step() {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  State& s = m_state;
  s.profile.clear();
  s.step_violation = 0;
  s.step_limit_violation = 0;
  s.impulse_predicted = false;  // solve_newton sets it for this step
  s.model_residual_known = false;  // and this
  m_budget_guard_tripped = false;
  const SolverDesc& cfg = m_model.solver;
  const auto lowered = [](int cap, int scene_cap) { return cap > 0 && cap < scene_cap; };
  const bool capped = lowered(s.caps.sqp, cfg.sqp_max_iterations) || lowered(s.caps.pgs, cfg.pgs_max_iterations) ||
                      lowered(s.caps.newton, cfg.newton_max_iterations) || lowered(s.caps.pcg, cfg.pcg_max_iterations);
  if (capped) {
    save_before_capped_attempt();
    s.profile.iterations["budget_guard_retries"] = 0;  // named on every capped step, not first mid-run
  }
  const bool sleeping = m_model.solver.sleep_steps > 0;
  if (sleeping) wake_disturbed_bodies(m_model, s);
  if (sleeping && s.sleep.all()) {
    rest_step();
    s.profile.step_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return true;
  }
  if (s.sleep.changed) apply_sleeping_set();
  const int asleep = s.sleep.count();  // during this step
  const Model& model = stage_model();
  const long factorizations = m_solver.factorizations(), solves = m_solver.solves(), rows = s.rows.appended;
  const VecX& x0 = s.scratch.attempt_x0 = s.x;
  const VecX& v0 = s.scratch.attempt_v0 = s.v;

  {
    StageTimer timer(s.profile, Stage::Assemble);
    assemble_system(model, s);
  }
  // The budget's PCG cap holds for every PCG solve of the step, the constraint stage's
  // (W's columns, the SQP's corrections) too; their counts and times by stage feed it back.
  m_solver.set_pcg_cap(s.caps.pcg);
  const LinearSolver::PcgTotals pcg_start = m_solver.pcg_totals();
  bool ok = model.has_hyperelastic ? solve_newton(model, m_solver, s) : solve_velocity(model, m_solver, s);
  const LinearSolver::PcgTotals pcg_middle = m_solver.pcg_totals();
  if (ok) solve_constraints(model, m_solver, s);  // times its own sub-stages
  // Caps below the scene's (the real-time budget) trade accuracy, not stability: a step they
  // left far outside a tolerance fails, and World::step retries it at the scene's caps (a
  // pressed finger under a 4 ms budget otherwise ran away, strain 1e4 and 1.6 m deep).
  if (ok && capped && s.step_violation > cfg.budget_violation_limit) {
    ok = false;
    m_budget_guard_tripped = true;
  }
  // Past any tolerance by orders of magnitude, at any caps: diverged (scene.hpp), retried or
  // stopped like a NaN rather than taken (NaN included). Attachment gaps are left out: a grab
  // pulled where the body cannot follow is not the solver's failure.
  if (ok && !(s.step_limit_violation <= cfg.divergence_violation_limit)) ok = false;
  if (!m_solver.uses_cholmod()) {
    const LinearSolver::PcgTotals& pcg_end = m_solver.pcg_totals();
    // Every step of a PCG scene, 0 included (a name first met in a warm step would allocate).
    s.profile.iterations["pcg"] = static_cast<int>(pcg_end.iterations - pcg_start.iterations);
    s.profile.iterations["pcg_solves"] = static_cast<int>(pcg_end.solves - pcg_start.solves);
    s.profile.iterations["pcg_unconverged"] = static_cast<int>(pcg_end.unconverged - pcg_start.unconverged);
    s.profile.pcg = {pcg_middle.ms - pcg_start.ms, pcg_end.ms - pcg_middle.ms,
                     static_cast<int>(pcg_middle.solves - pcg_start.solves),
                     static_cast<int>(pcg_end.solves - pcg_middle.solves)};
  }
  // Driven nodes are not unknowns of the constraint solve, which leaves them at rest:
  // give them back the step's prescribed mean velocity (set by solve_newton).
  if (ok)
    for (const DrivenNodes& driven : model.driven)
      for (int n : driven.nodes)
        s.v.segment<3>(3 * n) = (driven.position(m_model.rest_x.segment<3>(3 * n), s.t + m_model.h) -
                                 x0.segment<3>(3 * n)) / m_model.h;
  if (ok) {
    StageTimer timer(s.profile, Stage::Integrate);
    integrate_positions(model, s);
    // Finite but absurd counts as failed too: a diverging solve reaches 1e300 long before
    // it reaches Inf (seen on a collapsing column before its scene was fixed).
    ok = s.x.allFinite() && s.v.allFinite() && s.v.lpNorm<Eigen::Infinity>() <= m_model.solver.max_speed;
  }
  if (!ok) {
    // Roll back so that the caller keeps a valid state to report or write.
    s.x = x0;
    s.v = v0;
    s.profile.finite = false;
  } else {
    s.t += m_model.h;
    ++s.step_count;
    s.last_step_within_limits = s.step_limit_violation <= 1;
  }
  {
    StageTimer timer(s.profile, Stage::Surface);
    update_surfaces(model, s);
  }
  if (ok && sleeping) update_sleep(m_model, v0, s);
  if (asleep) s.profile.iterations["sleeping_bodies"] = asleep;
  s.profile.work.factorizations = m_solver.factorizations() - factorizations;
  s.profile.work.solves = m_solver.solves() - solves;
  s.profile.work.rows = s.rows.appended - rows;
  s.profile.step_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return ok;
}

double World::kinetic_energy() const {
  double ke = 0;
  for (int n = 0; n < m_model.num_nodes; ++n)
    ke += 0.5 * m_model.node_mass[n] * m_state.v.segment<3>(3 * n).squaredNorm();
  return ke;
}

uint64_t World::state_hash() const {
  uint64_t hash = 1469598103934665603ull;
  auto mix = [&](const VecX& values) {
    for (Eigen::Index i = 0; i < values.size(); ++i) {
      uint64_t bits;
      const double value = values[i];
      std::memcpy(&bits, &value, sizeof bits);
      for (int k = 0; k < 8; ++k) {
        hash ^= (bits >> (8 * k)) & 0xff;
        hash *= 1099511628211ull;
      }
    }
  };
  mix(m_state.x);
  mix(m_state.v);
  return hash;
}

std::vector<Vec3> initial_velocities(const SceneDesc& scene) {
  std::vector<Vec3> v;
  for (const BodyDesc& b : scene.bodies) v.push_back(b.velocity);
  return v;
}

}  // namespace sinew
