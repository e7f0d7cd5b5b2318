// solver.sqp_solves (solve_constraints.cpp): where W came from the rows' own columns
// Y = H^-1 J^T, SQP iterations after the first take J H^-1 r = Y^T r and one solve,
// v_k+1 = v_k + H^-1 (r + J^T lambda), instead of the Newton step and the correction apart.
// The same iterate in exact arithmetic: two creatures (the paper 000 scene, per-row
// Delassus path) in lockstep, the second taking the first's state before every step, end
// the same steps within the SQP's move tolerances of each other, with fewer solves.
#include <doctest/doctest.h>

#include "tests/engine/step/contact_scenes.hpp"
#include "tests/engine/step/lockstep.hpp"

using namespace sinew;
using namespace sinew::test;

TEST_CASE("sqp shared solve: the same steps of the creature end at the same iterates with fewer solves") {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_creature_500kPa_U100.json");
  scene.solver.sleep_steps = 0;
  scene.solver.sqp_solves = "separate";
  World separate = make_world(scene);
  scene.solver.sqp_solves = "shared";
  World shared = make_world(scene);
  const SolverDesc& solver = scene.solver;
  // As in test_sqp_conjugate_steps.cpp: each SQP stops once its last move is within the
  // position (or stall) tolerance; two stopped iterates are taken as within twice that.
  const double bound = 2 * std::max(solver.sqp_position_tolerance, solver.sqp_stall_tolerance);
  long separate_solves = 0, shared_solves = 0;
  int compared = 0, same_iterations = 0;
  double farthest = 0;
  bool same_factor = false;
  const int steps = 90;
  for (int i = 0; i < steps; ++i) {
    shared.mutable_state() = separate.state();
    REQUIRE(separate.step());
    REQUIRE(shared.step());
    const auto count = step_count_of;
    // Only where both hold the same factorisation (the copied state's H^-1 columns are
    // then this world's own) and neither line search ran out of halvings.
    same_factor = same_factorisation(same_factor, separate, shared);
    if (!same_factor || count(separate, "sqp_backtracks") > 0 || count(shared, "sqp_backtracks") > 0) continue;
    ++compared;
    if (count(separate, "sqp") == count(shared, "sqp")) {
      ++same_iterations;
      // Every QP after the first saves one solve on the per-row path, and no other.
      CHECK(shared.profile().work.solves <= separate.profile().work.solves);
      separate_solves += separate.profile().work.solves;
      shared_solves += shared.profile().work.solves;
    }
    farthest = std::max(farthest, farthest_node(separate.state().x, shared.state().x));
  }
  MESSAGE("over " << compared << " of " << steps << " steps (" << same_iterations << " with as many QPs): "
                  << separate_solves << " solves (separate) vs " << shared_solves << " (shared); farthest node apart "
                  << farthest << " m (bound " << bound << ")");
  CHECK(compared >= steps / 2);
  CHECK(same_iterations >= compared * 3 / 4);
  CHECK(shared_solves < separate_solves);
  CHECK(farthest <= bound);
}
