// The pair cuts (engine/constraints/strain_limit.hpp) on the finger of paper 001, fig. 3,
// pressed flat: where two principal stretches meet at the 1.02 limit of e3, the paper's
// rows alone let each QP step turn the largest stretch past its limit unseen, and the SQP
// needs more iterations to end within its tolerance (docs/ARCHITECTURE.md, "Why the pressed
// finger never settles"). With the cuts, fewer; both within the tolerance at every step.
#include "paper001_support.hpp"

using namespace sinew;
using namespace sinew::paper001;

namespace {

struct CutsRun {
  double worst_violation = 0;
  int sqp_iterations = 0;
  int capped_steps = 0;
  double tolerance = 0;
};

CutsRun run_flat_finger(const std::string& pair_cuts, int frames) {
  SceneDesc scene =
      load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_flat_anisotropic.json");
  scene.solver.sleep_steps = 0;  // as benchmarked: asleep, it would test nothing
  for (BodyDesc& body : scene.bodies) body.strain_limit.pair_cuts = pair_cuts;
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  CutsRun r;
  r.tolerance = world.model().solver.strain_tolerance;
  for (int f = 0; f < frames; ++f) {
    REQUIRE(world.step());
    r.worst_violation = std::max(r.worst_violation, worst_strain_limit_violation(world.model(), world.state().x));
    r.sqp_iterations += world.profile().iteration("sqp");
    if (world.profile().ended_at_sqp_cap(world.model().solver.sqp_max_iterations)) ++r.capped_steps;
  }
  MESSAGE("pair cuts " << pair_cuts << ": SQP iterations " << r.sqp_iterations << ", worst strain violation "
                       << r.worst_violation << ", steps at the cap " << r.capped_steps);
  return r;
}

}  // namespace

TEST_CASE("paper 001 fig. 3: pressed flat, the finger's SQP needs fewer iterations with the pair cuts") {
  const int frames = 120;
  const CutsRun off = run_flat_finger("off", frames), on = run_flat_finger("on", frames);
  CHECK(off.worst_violation <= off.tolerance);
  CHECK(on.worst_violation <= on.tolerance);
  CHECK(on.capped_steps == 0);
  // 301 -> 229 on the machines measured (2026-12-07); the runs are chaotic in round-off, so
  // only the direction is asserted, with a margin of a tenth.
  CHECK(on.sqp_iterations < 0.9 * off.sqp_iterations);
}
