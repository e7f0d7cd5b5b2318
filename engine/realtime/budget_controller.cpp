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
// Clamped as a double: a tiny cost could give a quotient past INT_MAX.
int fit(double available, double cost, int cap) {
  if (cost <= 0) return cap;
  return int(std::clamp(std::floor(std::max(available, 0.0) / cost), 1.0, double(cap)));
}

}  // namespace

IterationCaps BudgetController::caps(double elapsed_ms, int steps_left, const StepProfile& last,
                                     const FactorisationForecast& next) const {
  IterationCaps caps;
  if (last.step_ms <= 0 || steps_left <= 0) return caps;  // nothing measured yet: the scene's caps
  // After a step the budget guard redid at the scene's caps (World::step), this one runs at
  // them too: cut again from the redo's costs, it would likely be redone as well, paying for
  // two steps.
  if (count(last, "budget_guard_retries") > 0) return caps;
  const double per_step = (m_budget_ms - elapsed_ms) / steps_left;

  const int sqp = count(last, "sqp"), newton = count(last, "newton");
  const double sqp_ms = last.constraint_ms();
  // Newton iterations are the assemble + factorize + solve stages of a hyperelastic step.
  const double newton_ms =
      newton > 0 ? stage_ms(last, Stage::Assemble) + stage_ms(last, Stage::Factorize) + stage_ms(last, Stage::Solve) : 0;
  // The fixed part, with the next step's factorisation in it or not (curved_refactor_interval
  // keeps one for up to 16 steps: the step after such a run would be under-forecast by a
  // whole factorisation, and the one after a factorisation over-forecast).
  double factorisation_change = 0;
  if (next.known && newton == 0) {
    factorisation_change =
        (next.factorises ? next.factorize_ms : 0.0) - (last.ran(Stage::Factorize) ? stage_ms(last, Stage::Factorize) : 0.0);
  }
  // A step retried after the budget's caps left it outside its tolerances (World::step) is
  // judged by the attempt that stood: the rolled-back one would otherwise read as fixed cost
  // and cut the next step's caps to nothing, tripping the guard again.
  const double fixed_ms =
      std::max(0.0, last.step_ms - last.rolled_back_ms - sqp_ms - newton_ms + factorisation_change);
  const double per_sqp = sqp > 0 ? sqp_ms / sqp : 0, per_newton = newton > 0 ? newton_ms / newton : 0;

  caps.sqp = fit(per_step - fixed_ms - newton_ms, per_sqp, m_scene.sqp_max_iterations);
  const double left_after_one_sqp = per_step - fixed_ms - (sqp > 0 ? per_sqp : 0);
  caps.newton = fit(left_after_one_sqp, per_newton, m_scene.newton_max_iterations);
  // PGS sweeps in proportion to what the SQP iterations had of what they needed.
  const double sqp_share = per_sqp > 0 ? std::clamp((per_step - fixed_ms - newton_ms) / (per_sqp * std::max(sqp, 1)), 0.0, 1.0) : 1.0;
  caps.pgs = std::max(1, int(std::floor(sqp_share * m_scene.pgs_max_iterations)));
  // PCG iterations per solve (solver.linear "pcg"; the cap holds for all of a step's PCG
  // solves, the constraint stage's columns and corrections too): what fits in the time left
  // once the rest of the step is paid at the caps just set, SQP and Newton iterations and
  // the PCG solves they make cut in proportion, at the last step's cost per CG iteration.
  // Even when the rest alone overruns, PCG is cut to what is left (at least one iteration):
  // a fixed budget does the least it can.
  const int pcg = count(last, "pcg");
  const PcgWork& work = last.pcg;
  const double pcg_ms = work.step_ms + work.constraint_ms;
  if (pcg > 0 && pcg_ms > 0) {
    const double kept_sqp = sqp > 0 ? std::min(caps.sqp, sqp) / double(sqp) : 1.0;
    const double kept_newton = newton > 0 ? std::min(caps.newton, newton) / double(newton) : 1.0;
    // Stages 2-3's CG time sits in Newton's iterations on hyperelastic steps, else in the
    // fixed part; the constraint stage's in the SQP iterations.
    const double rest =
        (newton > 0 ? fixed_ms + kept_newton * std::max(0.0, newton_ms - work.step_ms) : std::max(0.0, fixed_ms - work.step_ms)) +
        kept_sqp * std::max(0.0, sqp_ms - work.constraint_ms);
    const double solves = std::max(1.0, std::round(work.step_solves * kept_newton + work.constraint_solves * kept_sqp));
    caps.pcg = fit((per_step - rest) / solves, pcg_ms / pcg, m_scene.pcg_max_iterations);
  }
  return caps;
}

}  // namespace sinew
