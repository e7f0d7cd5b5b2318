#pragma once
// A running simulation: the constant Model, the mutable State, and step().
#include <memory>

#include "engine/model.hpp"
#include "engine/solve/linear_solver.hpp"
#include "engine/state.hpp"

namespace sinew {

class World {
 public:
  explicit World(Model model, const std::vector<Vec3>& initial_velocity = {});

  // Advances by model().h. A step that meets a NaN/Inf, a system matrix it cannot
  // factorise, a node faster than solver.max_speed or a constraint (not an attachment) more
  // than solver.divergence_violation_limit tolerances past at its end is rolled back (one that
  // a real-time budget's caps left past budget_violation_limit is first redone at the scene's
  // caps) and retried afresh,
  // then as 2 and 4 sub-steps (profile().iterations["step_retries"] counts the failed
  // attempts). Returns false, with the state rolled back to the start of the step and
  // profile().finite == false, if every retry failed too.
  bool step();

  const Model& model() const { return m_model; }
  const State& state() const { return m_state; }
  State& mutable_state() { return m_state; }
  const StepProfile& profile() const { return m_state.profile; }
  // Whether the linear solver is CHOLMOD (not PCG): the one that can keep a factorisation.
  bool uses_cholmod() const { return m_solver.uses_cholmod(); }

  double kinetic_energy() const;
  // FNV-1a over the bit patterns of x and v: equal hashes mean identical states.
  uint64_t state_hash() const;

 private:
  // The model the stages run on: m_model, or m_frozen while some bodies sleep.
  const Model& stage_model() const { return m_frozen ? *m_frozen : m_model; }
  // After the sleeping set changed: the stages' model, its system pattern and the solver's
  // symbolic analysis follow, and the next step factorises afresh.
  void apply_sleeping_set();
  // A step while every body sleeps: only time advances.
  void rest_step();
  // One attempt at a step of m_model.h; on failure x and v are rolled back.
  bool attempt_step();
  void set_step_size(double h);  // of m_model and m_frozen
  // Drops what a step inherits from the previous one: factorisation, kept H^-1, multipliers,
  // curvature.
  void forget_previous_step();

  Model m_model;
  bool m_budget_guard_tripped = false;  // the last attempt_step failed the budget's violation limit
  // State a capped attempt (the real-time budget) may have to be redone from (world.cpp).
  struct CappedAttemptStart {
    int factor_age = 0, factor_sqp = -1;
    bool newton_factor_spent = false, keep_curved_factor = false, curvature_pending = false;
    RowTable curvature_rows;
    VecX curvature_point;
    std::vector<double> curvature;
    std::vector<std::pair<int, Eigen::Matrix<double, 12, 12>>> curvature_blocks;
    bool has_constraint_impulse = false, constraint_impulse_steady = false;
    VecX constraint_impulse;
  };
  CappedAttemptStart m_capped_start;
  void save_before_capped_attempt();
  void restore_before_capped_attempt();
  std::unique_ptr<Model> m_frozen;  // sleepers frozen (engine/sleep/sleep.hpp); null when all are awake
  State m_state;
  LinearSolver m_solver;
};

// Initial velocities per body from the scene (one per body).
std::vector<Vec3> initial_velocities(const SceneDesc& scene);

}  // namespace sinew
