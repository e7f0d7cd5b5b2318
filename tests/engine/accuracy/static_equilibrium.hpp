#pragma once
// Shared by the accuracy tests: a World from scene JSON text, stepped to static equilibrium.
// With a time step far longer than the slowest period (h omega >> 1), a backward Euler step
// is a fixed-point iteration on the static problem that shrinks the dynamic part of the
// state by about 1 / (h omega)^2, so a few steps reach equilibrium to round-off.
#include <doctest/doctest.h>

#include <string>

#include "engine/world.hpp"

namespace sinew::accuracy {

// Sleeping bodies (engine/sleep/) would freeze the iteration before it converges: off.
inline SceneDesc static_scene(const std::string& json) {
  SceneDesc scene = parse_scene_text(json, "accuracy", ".");
  scene.solver.sleep_steps = 0;
  return scene;
}

inline World make_world(const SceneDesc& scene) {
  return World(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
}

// Steps until no node moves more than `tolerance` (m) in a step, at most `max_steps`.
// Returns the steps taken; a failed step fails the test.
inline int settle(World& world, double tolerance, int max_steps) {
  for (int step = 1; step <= max_steps; ++step) {
    const VecX before = world.state().x;
    REQUIRE(world.step());
    if ((world.state().x - before).lpNorm<Eigen::Infinity>() <= tolerance) return step;
  }
  FAIL("not settled within " << max_steps << " steps");
  return max_steps;
}

}  // namespace sinew::accuracy
