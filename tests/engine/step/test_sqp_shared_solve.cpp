// solver.sqp_solves (solve_constraints.cpp): where W came from the rows' own columns
// Y = H^-1 J^T, SQP iterations after the first take J H^-1 r = Y^T r and one solve,
// v_k+1 = v_k + H^-1 (r + J^T lambda), instead of the Newton step and the correction apart,
// and the first QP's correction H^-1 J^T lambda = Y lambda takes no solve;
// where W came from a kept G (delassus_reuse), the W lambda_0 correction and the Newton step
// share one solve, J H^-1 (r + J^T lambda_0), before that update. The same iterates in exact
// arithmetic: two worlds in lockstep, the second taking the first's state before every
// step, end the same steps within the SQP's move tolerances of each other, with fewer solves.
#include <doctest/doctest.h>

#include "tests/engine/step/contact_scenes.hpp"
#include "tests/engine/step/lockstep.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

struct Lockstep {
  long separate_solves = 0, shared_solves = 0;
  int compared = 0, same_iterations = 0;
  double farthest = 0;
  double bound = 0;
};

// Runs SCENE "separate" and "shared" in lockstep for `steps` steps. Compares only where both
// hold the same factorisation (the copied state's H^-1 columns are then this world's own)
// and, with skip_line_searches, neither line search halved a step.
Lockstep run_lockstep(SceneDesc scene, int steps, bool skip_line_searches) {
  scene.solver.sleep_steps = 0;
  scene.solver.sqp_solves = "separate";
  World separate = make_world(scene);
  scene.solver.sqp_solves = "shared";
  World shared = make_world(scene);
  Lockstep out;
  // As in test_sqp_conjugate_steps.cpp: each SQP stops once its last move is within the
  // position (or stall) tolerance; two stopped iterates are taken as within twice that.
  out.bound = 2 * std::max(scene.solver.sqp_position_tolerance, scene.solver.sqp_stall_tolerance);
  bool same_factor = false;
  for (int i = 0; i < steps; ++i) {
    shared.mutable_state() = separate.state();
    REQUIRE(separate.step());
    REQUIRE(shared.step());
    const auto count = step_count_of;
    same_factor = same_factorisation(same_factor, separate, shared);
    if (!same_factor) continue;
    if (skip_line_searches && (count(separate, "sqp_backtracks") > 0 || count(shared, "sqp_backtracks") > 0)) continue;
    ++out.compared;
    if (count(separate, "sqp") == count(shared, "sqp")) {
      ++out.same_iterations;
      // Each QP saves one solve on the shared path (the first by Y lambda, later ones by
      // folding the Newton step into the correction's solve), and costs none.
      CHECK(shared.profile().work.solves <= separate.profile().work.solves);
      out.separate_solves += separate.profile().work.solves;
      out.shared_solves += shared.profile().work.solves;
    }
    out.farthest = std::max(out.farthest, farthest_node(separate.state().x, shared.state().x));
  }
  MESSAGE("over " << out.compared << " of " << steps << " steps (" << out.same_iterations << " with as many QPs): "
                  << out.separate_solves << " solves (separate) vs " << out.shared_solves
                  << " (shared); farthest node apart " << out.farthest << " m (bound " << out.bound << ")");
  return out;
}

SceneDesc paper_scene(const char* name) {
  return load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/" + name + ".json");
}

}  // namespace

TEST_CASE("sqp shared solve: the same steps of the creature end at the same iterates with fewer solves") {
  const int steps = 90;  // the paper 000 scene: per-row Delassus path
  const Lockstep r = run_lockstep(paper_scene("paper000_creature_500kPa_U100"), steps, true);
  CHECK(r.compared >= steps / 2);
  CHECK(r.same_iterations >= r.compared * 3 / 4);
  CHECK(r.shared_solves < r.separate_solves);
  CHECK(r.farthest <= r.bound);
}

TEST_CASE("sqp shared solve: with a kept G the finger's steps end at the same iterates with fewer solves") {
  // Paper 001's flat-pressed finger: strain rows on the touched-node path, G kept across
  // factorisations. Line searches included: the iterates agree to round-off, so do their
  // decisions (measured: 5e-12 m apart over 53 of 60 steps).
  const SceneDesc scene = paper_scene("paper001_finger_flat_anisotropic");
  REQUIRE(scene.solver.delassus_reuse > 1);
  const int steps = 60;
  const Lockstep r = run_lockstep(scene, steps, false);
  CHECK(r.compared >= steps / 2);
  CHECK(r.same_iterations >= r.compared / 2);
  CHECK(r.shared_solves < r.separate_solves);
  CHECK(r.farthest <= r.bound);
}
