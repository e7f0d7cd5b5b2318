// The SQP line search's restoration acceptance (solver.sqp_restoration, solve_constraints.cpp)
// on the finger of paper 001, fig. 3, pressed flat: a trial that brings an iterate past a
// tolerance within every one is taken whatever the l1 merit says. With the merit alone,
// full steps that took the worst strain row to a quarter of its tolerance were rejected
// (many rows each a little violated sum to more than the few before), and the halvings
// ended past the tolerance again, QP after QP. Taken, the steps need fewer QPs and fewer
// row builds, and every step still ends within the tolerance.
#include "paper001_support.hpp"

using namespace sinew;
using namespace sinew::paper001;

namespace {

struct RestorationRun {
  double worst_violation = 0;
  int sqp_iterations = 0;
  int backtracks = 0;
  int accepted = 0;  // sqp_restorations_accepted
  int capped_steps = 0;
  double tolerance = 0;
};

RestorationRun run_flat_finger_restoration(const std::string& restoration, int frames) {
  SceneDesc scene =
      load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_flat_anisotropic.json");
  scene.solver.sleep_steps = 0;  // as benchmarked
  scene.solver.sqp_restoration = restoration;
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  RestorationRun r;
  r.tolerance = world.model().solver.strain_tolerance;
  for (int f = 0; f < frames; ++f) {
    REQUIRE(world.step());
    r.worst_violation = std::max(r.worst_violation, worst_strain_limit_violation(world.model(), world.state().x));
    r.sqp_iterations += world.profile().iteration("sqp");
    r.backtracks += world.profile().iteration("sqp_backtracks");
    r.accepted += world.profile().iteration("sqp_restorations_accepted");
    if (world.profile().ended_at_sqp_cap(world.model().solver.sqp_max_iterations)) ++r.capped_steps;
  }
  MESSAGE("sqp_restoration " << restoration << ": SQP iterations " << r.sqp_iterations << ", backtracks "
                             << r.backtracks << ", restorations accepted " << r.accepted
                             << ", worst strain violation " << r.worst_violation << ", steps at the cap "
                             << r.capped_steps);
  return r;
}

}  // namespace

TEST_CASE("paper 001 fig. 3: pressed flat, taking the trials that restore the tolerances saves QPs and row builds") {
  const int frames = 120;
  const RestorationRun merit = run_flat_finger_restoration("none", frames);
  const RestorationRun accept = run_flat_finger_restoration("accept", frames);
  CHECK(merit.accepted == 0);
  CHECK(accept.accepted > 0);
  CHECK(merit.worst_violation <= merit.tolerance);
  CHECK(accept.worst_violation <= accept.tolerance);
  CHECK(accept.capped_steps == 0);
  // 262 -> 224 QPs here (2026-12-07, AMD EPYC); the runs are chaotic in round-off, so only
  // the direction is asserted. Each trial is a row build, as is each QP's iterate.
  CHECK(accept.sqp_iterations < merit.sqp_iterations);
  CHECK(accept.sqp_iterations + accept.backtracks < merit.sqp_iterations + merit.backtracks);
}
