// Results do not depend on the thread count (issue 7, section 2): shipped scenes run with 1
// and with 2 worker threads (tbb::global_control) end in bitwise the same x and v
// (World::state_hash). Each scene covers different parallel loops: hex assembly by colour,
// energy-limit and obstacle contact rows (creature), strain-limit rows and their curvature
// (paper 001 beam), hyperelastic Newton with its energies, derivatives and line search
// (paper 003 elbow), body-vs-body contact with the Embree refit (two boxes stacked).
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <string>

#include "engine/world.hpp"

using namespace sinew;

namespace {

SceneDesc shipped(const std::string& name) {
  return load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/" + name + ".json");
}

struct Run {
  uint64_t hash = 0;
  int steps = 0;  // that succeeded
  int rows = 0;   // most constraint rows of any step (shows the constraints were exercised)
  int contacts = 0;  // most contact rows of any step
};

Run run(const SceneDesc& scene, int steps, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  Run out;
  for (int i = 0; i < steps && world.step(); ++i) {
    ++out.steps;
    int rows = 0;
    for (const auto& [kind, n] : world.profile().rows) rows += n;
    out.rows = std::max(out.rows, rows);
    // StepWork::rows counts every row built in the step: at least the step's last table.
    // (It went negative when the count travelled with the row tables the SQP swaps.)
    CHECK(world.profile().work.rows >= rows);
    if (world.profile().rows.count("contact")) out.contacts = std::max(out.contacts, world.profile().rows.at("contact"));
  }
  out.hash = world.state_hash();
  return out;
}

void check_same_for_1_and_2_threads(const SceneDesc& scene, int steps, bool contact) {
  const Run one = run(scene, steps, 1), two = run(scene, steps, 2);
  CHECK(one.steps == steps);
  CHECK(two.steps == steps);
  CHECK(one.rows > 0);
  if (contact) CHECK(one.contacts > 0);
  CHECK(one.hash == two.hash);
}

}  // namespace

TEST_CASE("thread determinism: creature with an energy limit landing on the ground (hex, contact)") {
  // Dropped from 0.5 m: it touches the plane after ~19 steps; 40 steps include the impact.
  check_same_for_1_and_2_threads(shipped("paper000_creature_500kPa_U100"), 40, true);
}

TEST_CASE("thread determinism: strain-limited beam (tet, strain rows, SQP curvature)") {
  check_same_for_1_and_2_threads(shipped("paper001_beam_5kPa_isotropic"), 40, false);
}

TEST_CASE("thread determinism: side-pressed Stable Neo-Hookean finger (Newton, strain rows, curvature, contact)") {
  // The QPs start on Newton's H plus the last step's strain-row curvature (solve_newton.cpp).
  SceneDesc scene = shipped("paper001_finger_side_anisotropic");
  scene.bodies[0].material.model = "stable_neo_hookean";
  scene.bodies[0].damping_mass = 2;
  scene.bodies[0].damping_stiffness = 0;
  check_same_for_1_and_2_threads(scene, 30, true);
}

TEST_CASE("thread determinism: Stable Neo-Hookean elbow (Newton, driven nodes)") {
  SceneDesc scene = shipped("paper003_elbow_snh");
  // No constraint rows in this scene: checked by the Newton iterations instead.
  const int steps = 20;
  auto newton_run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
    int newton = 0;
    for (int i = 0; i < steps; ++i) {
      REQUIRE(world.step());
      newton += world.profile().iterations.at("newton");
    }
    return std::make_pair(world.state_hash(), newton);
  };
  const auto one = newton_run(1), two = newton_run(2);
  CHECK(one.second > steps);
  CHECK(one.second == two.second);
  CHECK(one.first == two.first);
}

TEST_CASE("thread determinism: a box dropped onto another (body-vs-body contact)") {
  // As the stacking test of test_solve_constraints_body_contact.cpp: coarse surfaces, since
  // body-vs-body rows are per vertex; the top box lands after ~4 steps.
  const SceneDesc scene = parse_scene_text(R"({"h": 0.0166666666666667,
    "bodies": [{"name": "bottom", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
                "transform": {"translate": [0.013, 0.1704, 0.007]}, "cell_size": 0.1, "surface_resolution": 0.085,
                "material": {"E": 1e6, "nu": 0.3, "rho": 500}},
               {"name": "top", "shape": [{"type": "box", "half_extents": [0.12, 0.12, 0.12]}],
                "transform": {"translate": [0.03, 0.47, 0.01]}, "cell_size": 0.08, "surface_resolution": 0.08,
                "material": {"E": 1e6, "nu": 0.3, "rho": 500}}],
    "obstacles": [{"type": "plane", "friction": 0.5}]})",
                                           "stack", ".");
  check_same_for_1_and_2_threads(scene, 20, true);
}
