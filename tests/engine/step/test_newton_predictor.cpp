// solver.newton_predictor (solve_newton.cpp, solve_constraints.cpp): Newton minimises the
// Lagrangian at the last step's multipliers (their impulse J^T lambda as a fixed force), and
// the SQP then finds the whole lambda from the true model's residual. Checked here: the same
// steps of a Stable Neo-Hookean box resting on its plane and then lifted off it end at the
// same constrained solution with and without the predictor (the force it adds is taken back
// where the QP drops it), and the resting box takes fewer QPs with it.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "tests/engine/step/lockstep.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

// assets/scenes/contact_snh_box_on_plane.json: a 0.3 x 0.2 x 0.2 m box of tets (Stable
// Neo-Hookean), tilted 8 degrees, dropped onto the plane y = 0; here with sleeping off and
// the given predictor, Newton settings and friction.
SceneDesc tet_box_on_plane(const char* predictor, const char* newton, double friction) {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/contact_snh_box_on_plane.json");
  scene.solver.sleep_steps = 0;
  scene.solver.newton_predictor = predictor;
  scene.obstacles.at(0).friction = friction;
  const SolverDesc& shipped = scene.solver;
  if (std::string(newton) == "converged") {
    scene.solver.newton_max_iterations = 40;
    scene.solver.newton_tolerance = 1e-10;
    scene.solver.refactor_interval = 1;
    scene.solver.delassus_reuse = 1;
  } else {
    REQUIRE(shipped.newton_max_iterations == 1);  // the shipped scene's real-time setting
    REQUIRE(shipped.refactor_interval == 8);
  }
  return scene;
}

World world_of(const SceneDesc& scene) { return World(build_model(scene, [](const std::string&) {})); }

double lowest_node(const World& w) {
  double lowest = 1e300;
  for (int n = 0; n < w.model().num_nodes; ++n) lowest = std::min(lowest, w.state().x[3 * n + 1]);
  return lowest;
}

// An upward force of twice the box's weight on every node (the lift-off).
void lift(World& w) {
  for (int n = 0; n < w.model().num_nodes; ++n)
    w.mutable_state().external_force[3 * n + 1] = 2 * 9.81 * w.model().node_mass[n];
}

}  // namespace

TEST_CASE("Newton predictor: the same steps end at the same constrained solution, lift-off included") {
  // Converged Newton and a factorisation every step. The SQP then solves the QP of the
  // quadratic model at Newton's result, with the predictor's force or without it: two
  // models of one objective centred at different points (measured, not bounded: this is
  // what the test would catch). Frictionless, so that each QP's solution is unique (with
  // Coulomb friction it need not be). Each SQP that converged stopped once its last move was
  // at most the position tolerance; moves shrinking at least 2x leave at most as much again,
  // so the two are within twice that (stalls accepted, restored or capped steps, and line
  // searches that ran out of halvings end otherwise: not compared).
  const char* converged = "converged";
  const SceneDesc scene = tet_box_on_plane("none", converged, 0.0);
  World plain = world_of(scene), predicted = world_of(tet_box_on_plane("impulse", converged, 0.0));
  const double bound = 2 * scene.solver.sqp_position_tolerance;
  const int settled_from = 20, rest_steps = 60, lift_steps = 12;
  int compared = 0, lift_compared = 0, with_predictor = 0;
  double farthest = 0;
  for (int i = 0; i < rest_steps + lift_steps; ++i) {
    CAPTURE(i);
    if (i == rest_steps) lift(plain);
    predicted.mutable_state() = plain.state();  // the impulse too: the plain world stores it as well
    REQUIRE(plain.step());
    REQUIRE(predicted.step());
    with_predictor += step_count_of(predicted, "newton_predicted");
    CHECK(step_count_of(plain, "newton_predicted") == 0);
    // The SQP solves the quadratic model at Newton's result, and the predictor moves that
    // point: through the landing the two differ by more than the SQP's tolerances (up to
    // 2.2e-4 m at the first impact, where the predicted step was the nearer of the two, 3.9e-5
    // against 2.6e-4 m, to the fixed point of re-solving the step with its own last impulse).
    // Compared from rest on, and where no line search ran out of halvings.
    const auto ended_otherwise = [&](const World& w) {
      return step_count_of(w, "sqp_backtracks") > 0 || step_count_of(w, "sqp_stalls_accepted") > 0 ||
             step_count_of(w, "sqp_restored") > 0 || step_count_of(w, "sqp") >= scene.solver.sqp_max_iterations;
    };
    if (i < settled_from || ended_otherwise(plain) || ended_otherwise(predicted)) continue;
    ++compared;
    lift_compared += i >= rest_steps;
    const double apart = farthest_node(plain.state().x, predicted.state().x);
    farthest = std::max(farthest, apart);
    CHECK(apart <= bound);
  }
  MESSAGE(compared << " of " << rest_steps + lift_steps << " steps compared (" << lift_compared << " of the lift's), " << with_predictor
                   << " with the predictor; farthest node apart " << farthest << " m (bound " << bound << ")");
  CHECK(with_predictor > rest_steps / 2);
  CHECK(compared > (rest_steps + lift_steps - settled_from) / 2);
  CHECK(lift_compared > lift_steps / 2);
  // Lifted off: no contact force held back the box, in either world.
  CHECK(lowest_node(plain) > 0.01);
  CHECK(lowest_node(predicted) > 0.01);
}

TEST_CASE("Newton predictor: a resting box takes fewer QPs with one Newton iteration and an older factor") {
  // The setting of sinew_bench_hyperelastic's one-iteration runs: between factorisations
  // the SQP's QPs are a stationary iteration preconditioned by the older factor; without the
  // predictor its first QP supplies the whole contact impulse and the next ones that
  // factor's error on it.
  const char* bench = "shipped";
  long sqp[2] = {0, 0};
  const char* predictors[2] = {"none", "impulse"};
  for (int p = 0; p < 2; ++p) {
    World w = world_of(tet_box_on_plane(predictors[p], bench, 0.5));
    for (int i = 0; i < 90; ++i) {
      CAPTURE(i);
      REQUIRE(w.step());
      if (i < 30) continue;  // landed and settling by then
      sqp[p] += step_count_of(w, "sqp");
      CHECK(w.profile().violation.at("penetration") <= w.model().solver.contact_tolerance);
    }
  }
  MESSAGE("QPs over steps 30-89: " << sqp[0] << " without the predictor, " << sqp[1] << " with it");
  CHECK(sqp[1] < sqp[0]);
}
