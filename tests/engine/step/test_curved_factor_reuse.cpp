// A factorisation carrying the constraints' curvature is kept while the steps after it
// converge in no more SQP iterations than the step that made it
// (solver.curved_refactor_interval, solve_velocity.cpp), and a line-search first trial that
// already meets every tolerance is taken whole (solve_constraints.cpp). Both on paper 001's
// side-pressed finger, whose settled steps factorised every step and halved their one QP
// step five times.
#include <doctest/doctest.h>

#include <string>

#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

const std::string kReusing = "reusing the factorisation of an earlier step";

SceneDesc side_finger(int curved_refactor_interval) {
  SceneDesc scene =
      load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_side_anisotropic.json");
  scene.solver.sleep_steps = 0;  // the settled steps are the ones under test
  scene.solver.curved_refactor_interval = curved_refactor_interval;
  return scene;
}

int count(const StepProfile& p, const char* name) { return p.iterations.count(name) ? p.iterations.at(name) : 0; }

}  // namespace

TEST_CASE("curved factor reuse: kept only while the next steps need no more SQP iterations") {
  const SceneDesc scene = side_finger(16);
  REQUIRE(scene.solver.refactor_interval == 1);  // every reuse below is the curved rule's
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  int baseline = -1;          // SQP iterations of the last step that factorised (-1: unknown)
  int previous_sqp = -1;      // of the step before
  bool previous_ok = false;   // that step converged within its tolerances, no refactorisation
  int reused = 0, run = 0, factorised = 0;
  // The line-search rule on the same run (one run for both: sanitizer builds run these too).
  int early_backtracks = 0, settled_backtracks = 0, converged_in_one = 0;
  for (int step = 0; step < 56; ++step) {
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    const int sqp = count(p, "sqp"), refactorised = count(p, "sqp_refactorisations");
    CAPTURE(step);
    if (step < 35) {
      early_backtracks += count(p, "sqp_backtracks");  // large steps while the press loads
    } else {
      settled_backtracks += count(p, "sqp_backtracks");
      if (sqp == 1) ++converged_in_one;
      // Every row table built is one iterate, the first or a QP's: no trial was halved.
      if (count(p, "sqp_backtracks") == 0) CHECK(p.work.row_builds == 1 + sqp + count(p, "sqp_restored"));
    }
    if (p.skipped[static_cast<int>(Stage::Factorize)] == kReusing) {
      // The rule's conditions, from the outside: the step before converged, refactorised
      // nothing and took at most the factorising step's SQP iterations; at most 15 in a row.
      CHECK(previous_ok);
      CHECK(previous_sqp >= 1);
      CHECK(previous_sqp <= baseline);
      ++reused;
      CHECK(++run < scene.solver.curved_refactor_interval);
    } else {
      run = 0;
      ++factorised;
      baseline = sqp;
    }
    if (refactorised) baseline = -1;  // its count includes iterations of an older factor
    previous_sqp = sqp;
    previous_ok = refactorised == 0 && sqp < scene.solver.sqp_max_iterations &&
                  (!p.violation.count("strain") || p.violation.at("strain") <= scene.solver.strain_tolerance);
    // Whichever factorisation served, the step meets the paper's claim's tolerance.
    if (p.violation.count("strain")) CHECK(p.violation.at("strain") <= scene.solver.strain_tolerance);
  }
  MESSAGE(reused << " steps reused a curved factorisation, " << factorised << " factorised");
  // Measured: 37 of 56 (from step ~15 on, most steps; settled, 15 in 16).
  CHECK(reused >= 20);
  // Settled (steps 35-55), the finger's QP steps mostly move nodes by less than
  // sqp_position_tolerance and meet every row; the merit's change at that scale is round-off
  // and the rows' second-order terms, which made 5 halvings (5 row builds, 1/32 of the step
  // taken) the rule on most of those steps (60 halvings there without the rule, checked).
  // With it only a step whose first trial misses a tolerance is halved: 0 in one rounding
  // of this run, 4 (on 2 of 21 steps) in another (the same arithmetic summed in another
  // order, 2026-12-05); a fifth of the 60 leaves room for such steps, not for the rule's loss.
  CHECK(early_backtracks > 0);  // the search still runs where steps are large
  REQUIRE(converged_in_one >= 10);  // the settled phase is what the window holds
  CHECK(settled_backtracks <= 12);
}

TEST_CASE("curved factor reuse: curved_refactor_interval 1 factorises every constrained step") {
  const SceneDesc scene = side_finger(1);
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  for (int step = 0; step < 20; ++step) {
    REQUIRE(world.step());
    CAPTURE(step);
    CHECK(world.profile().skipped[static_cast<int>(Stage::Factorize)] != kReusing);
  }
}

TEST_CASE("curved factor reuse: a factorisation whose rotations were forgotten is not reused") {
  // What world.cpp does at a retry, sub-steps or a change of the sleeping set: the next step
  // factorises, whatever keep_curved_factor says.
  World world(build_model(side_finger(16), [](const std::string&) {}), initial_velocities(side_finger(16)));
  int forced = 0;
  for (int step = 0; step < 44; ++step) {
    REQUIRE(world.step());
    if (step < 30 || !world.state().keep_curved_factor) continue;
    world.mutable_state().factor_rotations.clear();
    REQUIRE(world.step());
    CAPTURE(step);
    CHECK(world.profile().skipped[static_cast<int>(Stage::Factorize)] != kReusing);
    ++forced;
  }
  REQUIRE(forced >= 5);  // the settled steps keep their factorisation
}
