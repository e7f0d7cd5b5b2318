#include "engine/realtime/budget_controller.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {
namespace {

int count(const StepProfile& p, const char* key) {
  const auto it = p.iterations.find(key);
  return it == p.iterations.end() ? 0 : it->second;
}

double stage_ms(const StepProfile& p, Stage s) { return p.ms[static_cast<int>(s)]; }

// floor(available / cost) clamped to [1, cap]; the cap when the cost is unknown (zero).
int fit(double available, double cost, int cap) {
  if (cost <= 0) return cap;
  return std::clamp(int(std::floor(std::max(available, 0.0) / cost)), 1, cap);
}

}  // namespace

IterationCaps BudgetController::caps(double elapsed_ms, int steps_left, const StepProfile& last) const {
  IterationCaps caps;
  if (last.step_ms <= 0 || steps_left <= 0) return caps;  // nothing measured yet: the scene's caps
  const double per_step = (m_budget_ms - elapsed_ms) / steps_left;

  const int sqp = count(last, "sqp"), newton = count(last, "newton");
  const double sqp_ms = last.constraint_ms();
  // Newton iterations are the assemble + factorize + solve stages of a hyperelastic step.
  const double newton_ms =
      newton > 0 ? stage_ms(last, Stage::Assemble) + stage_ms(last, Stage::Factorize) + stage_ms(last, Stage::Solve) : 0;
  const double fixed_ms = std::max(0.0, last.step_ms - sqp_ms - newton_ms);
  const double per_sqp = sqp > 0 ? sqp_ms / sqp : 0, per_newton = newton > 0 ? newton_ms / newton : 0;

  caps.sqp = fit(per_step - fixed_ms - newton_ms, per_sqp, m_scene.sqp_max_iterations);
  const double left_after_one_sqp = per_step - fixed_ms - (sqp > 0 ? per_sqp : 0);
  caps.newton = fit(left_after_one_sqp, per_newton, m_scene.newton_max_iterations);
  // PGS sweeps in proportion to what the SQP iterations had of what they needed.
  const double sqp_share = per_sqp > 0 ? std::clamp((per_step - fixed_ms - newton_ms) / (per_sqp * std::max(sqp, 1)), 0.0, 1.0) : 1.0;
  caps.pgs = std::max(1, int(std::floor(sqp_share * m_scene.pgs_max_iterations)));
  // PCG iterations per solve (solver.linear "pcg"): what fits in the solve stage's share of
  // the time left, the rest of the step costing what it did. The solve stage also holds
  // non-CG work (Newton's line search), so this cost per iteration errs high.
  const int pcg = count(last, "pcg");
  const double solve_ms = stage_ms(last, Stage::Solve);
  if (pcg > 0 && solve_ms > 0) {
    const int solves = std::max(1, count(last, "pcg_solves"));
    caps.pcg = fit((per_step - (last.step_ms - solve_ms)) / solves, solve_ms / pcg, m_scene.pcg_max_iterations);
  }
  return caps;
}

}  // namespace sinew
