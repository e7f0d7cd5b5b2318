// Where SQP builds its first rows (solve_constraints.cpp). When v* strays from the
// start-of-step velocities v0 by more than a contact margin after a constrained step, the
// first QP is linearised at v0; rows at v* then serve an exact factorisation's early stop
// (and, otherwise, only as a fallback at the SQP cap), so with an earlier step's
// factorisation they are not built at all: a step builds one row table per QP iterate and
// line-search trial plus the first, no more.
#include <doctest/doctest.h>

#include <string>

#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

using namespace sinew;

TEST_CASE("sqp first rows: with an earlier factorisation, no rows are built at a v* it will not use") {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_flat_anisotropic.json");
  // Only the first step factorises: every later one reuses it, so no step's factorisation is
  // exact and v* can never end a step.
  scene.solver.refactor_interval = 1000;
  scene.solver.sleep_steps = 0;
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  REQUIRE(world.step());
  int at_start = 0, constrained = 0;
  for (int step = 1; step < 40; ++step) {
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    if (!p.iterations.count("sqp")) continue;  // the constraint stage was skipped
    ++constrained;
    const auto events = [&](const char* name) { return p.iterations.count(name) ? p.iterations.at(name) : 0; };
    at_start += events("sqp_linearised_at_start");
    CAPTURE(step);
    // One table for the first iterate (v0 or v*, never both), one per QP's iterate, one
    // per backtracking trial, one when the cap restores an earlier iterate.
    CHECK(p.work.row_builds ==
          1 + events("sqp") + events("sqp_backtracks") + events("sqp_restored"));
  }
  MESSAGE(constrained << " constrained steps, " << at_start << " linearised at v0");
  // The 200 N press drives v* through the table once it is on (h^2 F / m, ~4 mm per step at
  // full load, against a margin of a quarter of the 8.5 mm cell): the case under test occurs.
  REQUIRE(at_start >= 10);
}
