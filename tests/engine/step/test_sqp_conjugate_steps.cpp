// solver.sqp_acceleration (solve_constraints.cpp, sqp_merit.hpp): with an earlier step's
// factorisation (refactor_interval > 1) the SQP's QP steps are a stationary iteration on
// the true QP, preconditioned by the old H; with rows that carry no curvature, taking each
// step to the Lagrangian's minimiser along it and making it A-conjugate to the last one
// turns that iteration into conjugate gradients. Checked here: the step length is that
// minimiser, and on a box resting on a plane with friction the conjugate steps are taken,
// every step still converges within its tolerances, the box comes to the same rest, and it
// takes fewer QPs than the plain iteration.
#include <doctest/doctest.h>

#include "engine/step/sqp_merit.hpp"
#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

TEST_CASE("sqp conjugate steps: the first trial is the Lagrangian's minimiser along the step") {
  // L(alpha) = L(0) + alpha s + 1/2 alpha^2 c is least at -s / c.
  CHECK(MeritStep::first_trial(true, -0.75, 1.0) == 0.75);
  CHECK(MeritStep::first_trial(true, -1.5, 1.0) == 1.5);
  // Only with rows that carry no curvature (else A is not the Lagrangian's Hessian), a
  // positive curvature, and a minimiser in (0, 2): otherwise the QP's own step.
  CHECK(MeritStep::first_trial(false, -0.75, 1.0) == 1.0);
  CHECK(MeritStep::first_trial(true, -0.75, 0.0) == 1.0);
  CHECK(MeritStep::first_trial(true, 0.5, 1.0) == 1.0);   // not a descent of L
  CHECK(MeritStep::first_trial(true, -2.5, 1.0) == 1.0);  // past twice the QP's step
}

TEST_CASE("sqp conjugate steps: the same steps of the creature converge to the same solution in fewer QPs") {
  // Two worlds of the paper 000 creature (energy limits, friction), one with each setting,
  // in lockstep: before every step the second takes the first's state, so both solve the
  // same problem and may differ only by where each SQP stopped, provided they also hold the
  // same factorisation (refactor_interval 4: three of four steps solve with an older H).
  // That holds from a scheduled factorisation, made by both from the same state, until
  // either refactorises at a stall; only such steps are compared.
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_creature_500kPa_U100.json");
  scene.solver.sleep_steps = 0;
  REQUIRE(scene.solver.refactor_interval > 1);
  scene.solver.sqp_acceleration = "none";
  World plain = make_world(scene);
  scene.solver.sqp_acceleration = "conjugate";
  World conjugate = make_world(scene);
  const SolverDesc& solver = scene.solver;
  // Each SQP stops once its last move is at most the position tolerance (or, its moves no
  // longer halving, the stall tolerance); moves shrinking at least 2x leave at most as much
  // again to go, so two stopped iterates are within twice that of each other.
  const double bound = 2 * std::max(solver.sqp_position_tolerance, solver.sqp_stall_tolerance);
  long plain_sqp = 0, conjugate_sqp = 0, conjugate_steps = 0;
  int compared = 0, with_stale_factor = 0;
  double farthest = 0;
  bool same_factor = false;
  const int steps = 90;  // falls, lands at step ~20 and stands (it tips over after ~90)
  for (int i = 0; i < steps; ++i) {
    conjugate.mutable_state() = plain.state();
    REQUIRE(plain.step());
    REQUIRE(conjugate.step());
    auto count = [](const World& w, const char* key) {
      const auto& it = w.profile().iterations;
      return it.count(key) ? it.at(key) : 0L;
    };
    auto factorised = [](const World& w) { return w.profile().skipped[static_cast<int>(Stage::Factorize)].empty(); };
    CHECK(count(plain, "sqp_conjugate_steps") == 0);
    CHECK(count(conjugate, "sqp") < solver.sqp_max_iterations);  // converged, not capped
    for (const World* w : {&plain, &conjugate})
      if (w->profile().violation.count("penetration")) CHECK(w->profile().violation.at("penetration") <= solver.contact_tolerance);
    same_factor = (same_factor || (factorised(plain) && factorised(conjugate))) &&
                  count(plain, "sqp_refactorisations") == 0 && count(conjugate, "sqp_refactorisations") == 0;
    conjugate_steps += count(conjugate, "sqp_conjugate_steps");
    if (!same_factor) continue;
    ++compared;
    if (!plain.state().factor_exact) ++with_stale_factor;
    plain_sqp += count(plain, "sqp");
    conjugate_sqp += count(conjugate, "sqp");
    const VecX& a = plain.state().x;
    const VecX& b = conjugate.state().x;
    for (Eigen::Index n = 0; n < a.size() / 3; ++n) farthest = std::max(farthest, (a.segment<3>(3 * n) - b.segment<3>(3 * n)).norm());
  }
  MESSAGE("over " << compared << " of " << steps << " steps (" << with_stale_factor << " with an older H): " << plain_sqp
                  << " QPs (none) vs " << conjugate_sqp << " (conjugate, " << conjugate_steps
                  << " conjugate steps in all); farthest node apart after one step " << farthest << " m (bound " << bound
                  << ")");
  CHECK(compared >= steps / 2);
  CHECK(with_stale_factor >= compared / 2);
  CHECK(conjugate_steps > 0);
  CHECK(farthest <= bound);
  CHECK(conjugate_sqp < plain_sqp);
}
