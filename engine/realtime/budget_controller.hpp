#pragma once
// The fixed-budget loop's decision: before each step of a frame, iteration caps that fit
// what is left of the frame's simulation budget, from what the last step's iterations cost.
// The caps only ever lower the scene's (which remain the accuracy target); the step itself
// is never cut short, so a frame can still run over, and over-budget frames are counted.
//
// Per step: time left per remaining step L = (budget - elapsed) / steps left. The last
// step's cost splits into a fixed part (assembly, factorisation, integration...), Newton
// iterations (assemble + factorize + solve per iteration, hyperelastic bodies) and SQP
// iterations (rows + solves + PGS + the line search's products per iteration). The SQP cap is what fits after the fixed
// part and the Newton iterations: floor((L - fixed - newton) / cost per SQP iteration); if
// that is below one, the Newton cap is cut the same way and PGS sweeps are scaled down in
// proportion. PCG iterations per solve (solver.linear "pcg", every PCG solve of the step):
// what fits in L less the rest of the step at those caps, over its PCG solves (cut with the
// SQP and Newton iterations that make them), at the last step's cost per CG iteration.
// Newton's CG preconditioned by an older factorisation keeps its own cap: cut further, its
// directions destabilised the bunny_5 drop under a 5 ms budget (3 runs of 3 blew up, none of
// 9 without the cut; bench/results/README.md, session 32).
// Every cap stays >= 1: a step always makes progress.
#include "engine/profile.hpp"
#include "engine/scene/scene.hpp"

namespace sinew {

// What the next step will do with the factorisation (stages 2-3 of a scene without
// hyperelastic bodies, whose Newton iterations are forecast on their own): a step that
// reuses one costs the last step's time less its factorisation, and one that factorises
// after a step that reused costs the last factorisation's time more.
struct FactorisationForecast {
  bool known = false;        // false: the last step's fixed part as it was
  bool factorises = false;   // the next step factorises (reuses_factorisation, stages.hpp)
  double factorize_ms = 0;   // the last factorisation's time (0: none measured yet)
};

class BudgetController {
 public:
  BudgetController(const SolverDesc& scene, double budget_ms) : m_scene(scene), m_budget_ms(budget_ms) {}

  // Caps for the next step: `elapsed_ms` spent on this frame so far, `steps_left` steps of it
  // still to run (this one included), `last` the previous step's profile (empty before the first:
  // the scene's caps).
  IterationCaps caps(double elapsed_ms, int steps_left, const StepProfile& last,
                     const FactorisationForecast& next = {}) const;

  double budget_ms() const { return m_budget_ms; }

 private:
  SolverDesc m_scene;
  double m_budget_ms;
};

}  // namespace sinew
