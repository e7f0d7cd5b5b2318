// The budget's caps from measured costs (synthetic profiles: no clock involved), and the
// solver stages honouring the caps.
#include <doctest/doctest.h>

#include <cmath>

#include <limits>

#include "engine/realtime/budget_controller.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

// A step that spent 1 ms on fixed work and `sqp` SQP iterations of 2 ms each (rows 0.5,
// solves 0.75, PGS 0.5, the line search's products 0.25 per iteration).
StepProfile linear_step(int sqp) {
  StepProfile p;
  p.ms[static_cast<int>(Stage::Assemble)] = 0.6;
  p.ms[static_cast<int>(Stage::Factorize)] = 0.3;
  p.ms[static_cast<int>(Stage::Integrate)] = 0.1;
  p.ms[static_cast<int>(Stage::Rows)] = 0.5 * sqp;
  p.ms[static_cast<int>(Stage::SqpSolve)] = 0.75 * sqp;
  p.ms[static_cast<int>(Stage::Pgs)] = 0.5 * sqp;
  p.ms[static_cast<int>(Stage::SqpMerit)] = 0.25 * sqp;
  p.iterations["sqp"] = sqp;
  p.step_ms = 1.0 + 2.0 * sqp;
  return p;
}

}  // namespace

TEST_CASE("budget controller: SQP caps are what fits in the time left per step") {
  SolverDesc scene;
  scene.sqp_max_iterations = 10;
  scene.pgs_max_iterations = 200;
  const BudgetController budget(scene, 16.0);
  // Nothing measured yet: the scene's caps.
  CHECK(budget.caps(0, 1, StepProfile{}).sqp == 0);
  // One step of 16 ms: 1 ms fixed, 15 ms for SQP at 2 ms each -> 7 iterations.
  CHECK(budget.caps(0, 1, linear_step(4)).sqp == 7);
  // Two steps left and 4 ms gone: 6 ms each -> (6 - 1) / 2 = 2 iterations.
  CHECK(budget.caps(4, 2, linear_step(4)).sqp == 2);
  // Plenty of time: the scene's cap, never more.
  CHECK(budget.caps(0, 1, linear_step(1)).sqp == 7);
  CHECK(BudgetController(scene, 1000).caps(0, 1, linear_step(4)).sqp == 10);
  CHECK(BudgetController(scene, 1000).caps(0, 1, linear_step(4)).pgs == 200);
  // Over budget already: one iteration (a step always progresses), PGS cut down.
  const IterationCaps late = budget.caps(20, 1, linear_step(4));
  CHECK(late.sqp == 1);
  CHECK(late.pgs == 1);
}

TEST_CASE("budget controller: the next step's factorisation is forecast, not the last step's repeated") {
  SolverDesc scene;
  scene.sqp_max_iterations = 20;
  const BudgetController budget(scene, 16.0);
  // The last step factorised (0.3 ms of its 1 ms fixed part).
  const StepProfile factorised = linear_step(4);
  StepProfile reused = linear_step(4);  // the same, but it kept an earlier factorisation
  reused.ms[static_cast<int>(Stage::Factorize)] = 0;
  reused.skipped[static_cast<int>(Stage::Factorize)] = "reusing the factorisation of an earlier step";
  reused.step_ms -= 0.3;
  FactorisationForecast next;
  next.known = true;
  // After a step that reused it, a factorisation of 5 ms is due: fixed 0.7 + 5 ms, so
  // floor((16 - 5.7) / 2) = 5 SQP iterations (without the forecast: floor(15.3 / 2) = 7).
  next.factorises = true;
  next.factorize_ms = 5.0;
  CHECK(budget.caps(0, 1, reused, next).sqp == 5);
  CHECK(budget.caps(0, 1, reused).sqp == 7);
  // After a step the guard redid, the scene's caps (0: none lowered).
  StepProfile redone = reused;
  redone.iterations["budget_guard_retries"] = 1;
  CHECK(budget.caps(0, 1, redone, next).sqp == 0);
  // After a step that factorised, the next keeps it: its fixed part is the last one's less
  // the factorisation.
  next.factorises = false;
  StepProfile heavy = linear_step(4);  // a 2.5 ms factorisation in a 3.2 ms fixed part
  heavy.ms[static_cast<int>(Stage::Factorize)] = 2.5;
  heavy.step_ms += 2.2;
  CHECK(budget.caps(0, 1, heavy, next).sqp == 7);   // floor((16 - 0.7) / 2)
  CHECK(budget.caps(0, 1, heavy).sqp == 6);         // floor((16 - 3.2) / 2)
  // Both factorise: the last one's time stands for the next one's.
  next.factorises = true;
  next.factorize_ms = 2.5;
  CHECK(budget.caps(0, 1, heavy, next).sqp == 6);
}

TEST_CASE("budget controller: Newton caps for hyperelastic steps") {
  SolverDesc scene;
  scene.newton_max_iterations = 20;
  StepProfile p;  // 3 Newton iterations of 2 ms (assemble 1, factorize 0.8, solve 0.2), 0.5 ms fixed
  p.ms[static_cast<int>(Stage::Assemble)] = 3;
  p.ms[static_cast<int>(Stage::Factorize)] = 2.4;
  p.ms[static_cast<int>(Stage::Solve)] = 0.6;
  p.iterations["newton"] = 3;
  p.step_ms = 6.5;
  CHECK(BudgetController(scene, 10).caps(0, 1, p).newton == 4);  // (10 - 0.5) / 2
  CHECK(BudgetController(scene, 1).caps(0, 1, p).newton == 1);
}

TEST_CASE("budget controller: PCG caps per solve are what fits in the time left") {
  SolverDesc scene;
  scene.pcg_max_iterations = 1000;
  StepProfile p;  // 10 ms: 2 ms outside the solve stage, two CG solves of 40 iterations at 0.1 ms
  p.ms[static_cast<int>(Stage::Assemble)] = 2;
  p.ms[static_cast<int>(Stage::Solve)] = 8;
  p.iterations["pcg"] = 80;
  p.iterations["pcg_solves"] = 2;
  p.pcg = {8, 0, 2, 0};
  p.step_ms = 10;
  CHECK(BudgetController(scene, 6).caps(0, 1, p).pcg == 20);  // (6 - 2) / 2 solves / 0.1 ms
  CHECK(BudgetController(scene, 12).caps(2, 2, p).pcg == 15);  // 5 ms per step left: (5 - 2) / 2 / 0.1
  CHECK(BudgetController(scene, 1e6).caps(0, 1, p).pcg == 1000);  // never above the scene's
  CHECK(BudgetController(scene, 1).caps(0, 1, p).pcg == 1);  // over budget: one iteration a solve
  // Newton's CG preconditioned by an older factorisation keeps its own cap: not counted.
  StepProfile newton = p;
  newton.iterations.clear();
  newton.iterations["newton"] = 2;
  newton.iterations["newton_pcg"] = 80;
  newton.pcg = {};
  CHECK(BudgetController(scene, 6).caps(0, 1, newton).pcg == 0);
  // No CG last step: the scene's caps.
  CHECK(BudgetController(scene, 6).caps(0, 1, linear_step(2)).pcg == 0);
}

TEST_CASE("budget controller: the PCG cap counts the rest of the step at its new caps") {
  SolverDesc scene;
  scene.sqp_max_iterations = 10;
  scene.newton_max_iterations = 10;
  scene.pcg_max_iterations = 1000;
  // Linear path, 10 ms: 1 ms fixed, a 4 ms PCG solve of 40 iterations, 5 SQP iterations of
  // 1 ms, in which 10 PCG solves (constraint columns) took 25 iterations, 2.5 ms.
  StepProfile p = linear_step(0);
  p.ms[static_cast<int>(Stage::Assemble)] = 1;
  p.ms[static_cast<int>(Stage::Factorize)] = 0;
  p.ms[static_cast<int>(Stage::Integrate)] = 0;
  p.ms[static_cast<int>(Stage::Solve)] = 4;
  p.ms[static_cast<int>(Stage::Rows)] = 5;
  p.iterations["sqp"] = 5;
  p.iterations["pcg"] = 65;
  p.iterations["pcg_solves"] = 11;
  p.pcg = {4, 2.5, 1, 10};
  p.step_ms = 10;
  // 6 ms: SQP cut to (6 - 5) / 1 = 1 iteration, a fifth: the rest costs 1 + 2.5 / 5 = 1.5 ms
  // and makes 1 + 10 / 5 = 3 PCG solves, which share 4.5 ms at 0.1 ms an iteration: 15. Charged
  // the 5 SQP iterations of the last step, it would have had 1 each.
  const IterationCaps linear = BudgetController(scene, 6).caps(0, 1, p);
  CHECK(linear.sqp == 1);
  CHECK(linear.pcg == 15);
  // Newton path, 14 ms: 2 iterations of assemble 2 + solve 4 (two PCG solves of 40
  // iterations), 2 ms fixed. At 8 ms: Newton cut to (8 - 2) / 6 = 1 iteration, so one PCG
  // solve next time, with 8 - 2 - 2 = 4 ms: 40 iterations.
  StepProfile q;
  q.ms[static_cast<int>(Stage::Assemble)] = 4;
  q.ms[static_cast<int>(Stage::Solve)] = 8;
  q.ms[static_cast<int>(Stage::Integrate)] = 2;
  q.iterations["newton"] = 2;
  q.iterations["pcg"] = 80;
  q.iterations["pcg_solves"] = 2;
  q.pcg = {8, 0, 2, 0};
  q.step_ms = 14;
  const IterationCaps newton = BudgetController(scene, 8).caps(0, 1, q);
  CHECK(newton.newton == 1);
  CHECK(newton.pcg == 40);
}

TEST_CASE("iteration caps: PCG solves honour the budget's cap and report stopping above tolerance") {
  const std::string text = R"({"gravity": [0, -9.81, 0], "solver": {"linear": "pcg"},
    "bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.3, 0.1, 0.1]}], "cell_size": 0.05,
      "material": {"E": 1e6, "nu": 0.3, "rho": 1000},
      "fixed": [{"half_space": {"point": [-0.29, 0, 0], "normal": [1, 0, 0]}}]}]})";
  const auto run = [&](int cap, int& most, int& unconverged) {
    World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
    most = unconverged = 0;
    for (int s = 0; s < 10; ++s) {
      world.mutable_state().caps.pcg = cap;
      REQUIRE(world.step());
      const auto& it = world.profile().iterations;
      REQUIRE(it.at("pcg_solves") == 1);  // the velocity solve; no constraint
      most = std::max(most, it.at("pcg"));
      unconverged += it.count("pcg_unconverged") ? it.at("pcg_unconverged") : 0;
    }
  };
  int most = 0, unconverged = 0;
  run(0, most, unconverged);
  CHECK(most > 3);  // the scene's solve needs more than the cap below
  CHECK(unconverged == 0);
  run(3, most, unconverged);
  CHECK(most == 3);
  CHECK(unconverged == 10);
}

TEST_CASE("iteration caps: the PCG cap holds for the constraint stage's solves, counted by stage") {
  // A box landing on a plane with PCG: the contact rows' columns of H^-1 and the SQP's
  // corrections are PCG solves too, cut alike and reported apart from the velocity solve.
  // One CG iteration a solve leaves the box over 1 mm (10 contact tolerances) deep on some
  // steps: the budget guard, which would redo those at the scene's caps, is off here (it is
  // tested below).
  const std::string text = R"({"gravity": [0, -9.81, 0], "solver": {"linear": "pcg", "budget_violation_limit": 1e300},
    "bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
      "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}],
    "obstacles": [{"type": "plane", "point": [0, -0.12, 0], "normal": [0, 1, 0]}]})";
  World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
  int touching = 0;
  for (int s = 0; s < 40; ++s) {
    world.mutable_state().caps.pcg = 1;
    REQUIRE(world.step());
    const StepProfile& profile = world.profile();
    const int solves = profile.iterations.at("pcg_solves");
    CHECK(profile.iterations.at("pcg") <= solves);  // one iteration each at most
    CHECK(solves == profile.pcg.step_solves + profile.pcg.constraint_solves);
    CHECK(profile.pcg.step_solves == 1);
    if (profile.pcg.constraint_solves > 0) ++touching;
  }
  CHECK(touching > 10);  // it landed: the constraint stage solved by PCG
}

TEST_CASE("iteration caps: Newton's PCG solves (solver.linear \"pcg\") honour the budget's cap") {
  const std::string text = R"({"gravity": [0, -9.81, 0], "solver": {"linear": "pcg", "newton_max_iterations": 2},
    "bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.3, 0.1, 0.1]}], "cell_size": 0.05,
      "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 1000},
      "fixed": [{"half_space": {"point": [-0.29, 0, 0], "normal": [1, 0, 0]}}]}]})";
  World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
  int unconverged = 0;
  for (int s = 0; s < 6; ++s) {
    world.mutable_state().caps.pcg = 2;
    REQUIRE(world.step());
    const auto& it = world.profile().iterations;
    REQUIRE(it.at("pcg_solves") >= 1);
    CHECK(it.at("pcg") <= 2 * it.at("pcg_solves"));
    unconverged += it.at("pcg_unconverged");
  }
  CHECK(unconverged > 0);  // two iterations do not reach pcg_tolerance 1e-8
}

TEST_CASE("iteration caps: Newton's CG preconditioned by an older factorisation ignores the PCG cap") {
  const std::string text = R"({"gravity": [0, -9.81, 0], "solver": {"refactor_interval": 8, "newton_max_iterations": 1},
    "bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.3, 0.1, 0.1]}], "cell_size": 0.05,
      "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 1000},
      "fixed": [{"half_space": {"point": [-0.29, 0, 0], "normal": [1, 0, 0]}}]}]})";
  const auto run = [&](int cap, int& most) {
    World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
    most = 0;
    for (int s = 0; s < 8; ++s) {
      world.mutable_state().caps.pcg = cap;
      REQUIRE(world.step());
      const auto& it = world.profile().iterations;
      most = std::max(most, it.count("newton_pcg") ? it.at("newton_pcg") : 0);
    }
    return world.state_hash();
  };
  int most_uncapped = 0, most_capped = 0;
  const auto uncapped = run(0, most_uncapped);
  CHECK(run(1, most_capped) == uncapped);
  CHECK(most_capped == most_uncapped);
  CHECK(most_capped > 1);  // the cap would have cut them
}

TEST_CASE("iteration caps: a step honours caps below the scene's") {
  const std::string text = R"({"gravity": [0, -9.81, 0], "solver": {"sqp_max_iterations": 10},
    "bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
      "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}],
    "obstacles": [{"type": "plane", "point": [0, -0.12, 0], "normal": [0, 1, 0]}]})";
  World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
  int most_sqp = 0, most_pgs = 0;
  world.mutable_state().caps = IterationCaps{1, 3, 0};
  for (int s = 0; s < 30; ++s) {
    REQUIRE(world.step());
    const auto& it = world.profile().iterations;
    most_sqp = std::max(most_sqp, it.count("sqp") ? it.at("sqp") : 0);
    most_pgs = std::max(most_pgs, it.count("pgs") ? it.at("pgs") : 0);
  }
  CHECK(most_sqp == 1);
  CHECK(most_pgs <= 3);  // one SQP iteration of at most 3 sweeps
  CHECK(most_pgs >= 1);  // the box did land: the LCP ran
}

namespace {

// The flat-pressed finger with every step capped at one QP of one PGS sweep (what a tight
// budget sets), without sleep; the worst step_violation seen and the guard's retries.
struct CappedRun {
  double worst = 0;
  int guard_retries = 0;
};

CappedRun run_capped_finger(double violation_limit, int steps, bool at_scene_caps = false) {
  SceneDesc scene =
      load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_flat_anisotropic.json");
  scene.solver.sleep_steps = 0;
  scene.solver.budget_violation_limit = violation_limit;
  // Unguarded: no divergence test either, which would otherwise retry those steps at the
  // scene's caps (World::step) before the budget guard could show.
  if (!std::isfinite(violation_limit)) scene.solver.divergence_violation_limit = violation_limit;
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  CappedRun run;
  for (int step = 0; step < steps; ++step) {
    // At the scene's own caps the budget lowers nothing: the guard must not act.
    world.mutable_state().caps.sqp = at_scene_caps ? scene.solver.sqp_max_iterations : 1;
    world.mutable_state().caps.pgs = at_scene_caps ? scene.solver.pgs_max_iterations : 1;
    REQUIRE(world.step());
    run.worst = std::max(run.worst, world.state().step_violation);
    const auto& it = world.profile().iterations;
    if (it.count("budget_guard_retries")) run.guard_retries += it.at("budget_guard_retries");
  }
  return run;
}

}  // namespace

TEST_CASE("budget guard: a step the caps leave past budget_violation_limit is redone at the scene's caps") {
  // Without the guard (a limit no step reaches) the capped finger ends its very first step
  // ~1,000 tolerances past a limit (and 4.3e6 within 40 steps). Four steps: each guarded one
  // is redone at the scene's caps, the cost of this test (sanitizer builds run it too).
  const CappedRun unguarded = run_capped_finger(std::numeric_limits<double>::infinity(), 4);
  REQUIRE(unguarded.worst > 10);
  // With it, no step ends past the limit; the steps that would have are redone.
  const CappedRun guarded = run_capped_finger(10, 4);
  CHECK(guarded.worst <= 10);
  CHECK(guarded.guard_retries > 0);
  // Caps that lower nothing never trip it, whatever the limit.
  CHECK(run_capped_finger(1e-300, 4, true).guard_retries == 0);
  MESSAGE("worst violation over tolerance: " << unguarded.worst << " unguarded, " << guarded.worst << " guarded ("
                                             << guarded.guard_retries << " steps redone)");
}
