// solver.sqp_acceleration (solve_constraints.cpp, sqp_merit.hpp): with an earlier step's
// factorisation (refactor_interval > 1) the SQP's QP steps are a stationary iteration on
// the true QP, preconditioned by the old H; with rows that carry no curvature, taking each
// step to the Lagrangian's minimiser along it and making it A-conjugate to the last one
// turns that iteration into conjugate gradients. Checked here: the step length is that
// minimiser, and on the paper 000 creature (contacts with friction, energy limits) the
// conjugate steps are taken, the same steps end within the SQP's move tolerances of each
// other, and they take fewer QPs. (Not a claim for every scene: a box settling on a plane,
// whose steps take two QPs either way, took 213 conjugate against 210 plain.)
#include <doctest/doctest.h>

#include "engine/step/sqp_merit.hpp"
#include "tests/engine/step/contact_scenes.hpp"
#include "tests/engine/step/lockstep.hpp"

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
  int compared = 0, with_stale_factor = 0, compared_positions = 0;
  double farthest = 0;
  bool same_factor = false;
  const int steps = 90;  // falls, lands at step ~20 and stands (it tips over after ~90)
  for (int i = 0; i < steps; ++i) {
    conjugate.mutable_state() = plain.state();
    REQUIRE(plain.step());
    REQUIRE(conjugate.step());
    const auto count = step_count_of;
    CHECK(count(plain, "sqp_conjugate_steps") == 0);
    same_factor = same_factorisation(same_factor, plain, conjugate);
    conjugate_steps += count(conjugate, "sqp_conjugate_steps");
    // Elsewhere the copied state holds H^-1 columns of the other world's factorisation: a
    // state the engine never produces, so nothing is checked there.
    if (!same_factor) continue;
    ++compared;
    if (!plain.state().factor_exact) ++with_stale_factor;
    // Conservative: a step converging at exactly the cap would count as not converged.
    CHECK(count(conjugate, "sqp") < solver.sqp_max_iterations);
    for (const World* w : {&plain, &conjugate})
      if (w->profile().violation.count("penetration")) CHECK(w->profile().violation.at("penetration") <= solver.contact_tolerance);
    plain_sqp += count(plain, "sqp");
    conjugate_sqp += count(conjugate, "sqp");
    // A step whose line search ran out of halvings ends there (its move, 1/32 of the QP's
    // step, passes the move test) without the bound below: compared only where neither did.
    if (count(plain, "sqp_backtracks") > 0 || count(conjugate, "sqp_backtracks") > 0) continue;
    ++compared_positions;
    farthest = std::max(farthest, farthest_node(plain.state().x, conjugate.state().x));
  }
  MESSAGE("over " << compared << " of " << steps << " steps (" << with_stale_factor << " with an older H): " << plain_sqp
                  << " QPs (none) vs " << conjugate_sqp << " (conjugate, " << conjugate_steps
                  << " conjugate steps in all); farthest node apart after one step " << farthest << " m (bound " << bound
                  << ")");
  CHECK(compared >= steps / 2);
  CHECK(with_stale_factor >= compared / 2);
  CHECK(compared_positions >= compared * 3 / 4);
  CHECK(conjugate_steps > 0);
  CHECK(farthest <= bound);
  // The steps compared are mostly easy ones (a stall refactorisation in either run ends
  // the comparison until both refactorise again): not more QPs there ...
  CHECK(conjugate_sqp <= plain_sqp);
}

TEST_CASE("sqp conjugate steps: the creature's run takes fewer QPs and stall refactorisations") {
  // ... and over the scene's run (not the same problems step for step once the runs part):
  // measured 646 -> 608 QPs and 34 -> 19 stall refactorisations over 180 frames.
  long sqp[2] = {0, 0}, refactorisations[2] = {0, 0};
  int variant = 0;
  for (const char* acceleration : {"none", "conjugate"}) {
    SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_creature_500kPa_U100.json");
    scene.solver.sqp_acceleration = acceleration;
    World world = make_world(scene);
    for (int i = 0; i < 180; ++i) {
      REQUIRE(world.step());
      const auto& it = world.profile().iterations;
      if (it.count("sqp")) sqp[variant] += it.at("sqp");
      if (it.count("sqp_refactorisations")) refactorisations[variant] += it.at("sqp_refactorisations");
    }
    ++variant;
  }
  MESSAGE("180 frames: " << sqp[0] << " -> " << sqp[1] << " QPs, " << refactorisations[0] << " -> " << refactorisations[1]
                         << " stall refactorisations");
  CHECK(sqp[1] < sqp[0]);
  CHECK(refactorisations[1] < refactorisations[0]);
}
