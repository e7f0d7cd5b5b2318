// The quadratic model solve_newton hands to the constraint stage (solve_newton.cpp, its end)
// leaves out what Newton left of its gradient when that is more than a tenth of the step's
// scale. When it was kept whatever its size, every step with one active row took the
// model's whole Newton step from the result, never line-searched on Phi, and a soft box
// dropped from 1 m with one Newton iteration a step gained kinetic energy from nothing at its
// landing until it stopped (frame 34, 1.2e7 J).
// Checked here on that drop: every step is taken, and the kinetic energy never exceeds the
// potential energy the box had at the start above the plane, which bounds it for a step that
// creates no energy (backward Euler, mass damping, friction and inelastic contact all
// dissipate; the elastic energy and the height above the plane cannot go negative).
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

// assets/scenes/contact_snh_box_on_plane.json (one Newton iteration a step, refactor_interval
// 8): the 0.3 x 0.2 x 0.2 m Stable Neo-Hookean box of tets, here at E 50 kPa with its centre
// 1 m above the plane, sleeping off.
SceneDesc soft_box_dropped_from_a_metre() {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/contact_snh_box_on_plane.json");
  REQUIRE(scene.solver.newton_max_iterations == 1);
  scene.solver.sleep_steps = 0;
  scene.bodies.at(0).material.E = 5e4;
  scene.bodies.at(0).translate.y() = 1.0;
  return scene;
}

}  // namespace

TEST_CASE("Newton model: a soft box dropped with one Newton iteration a step gains no energy at its landing") {
  World world(build_model(soft_box_dropped_from_a_metre(), [](const std::string&) {}));
  const Model& model = world.model();
  const Vec3 gravity = model.gravity;
  REQUIRE(gravity.y() < 0);  // down the plane's normal, its potential energy g y per mass
  REQUIRE(gravity.x() == 0);
  REQUIRE(gravity.z() == 0);
  // Potential energy above the plane y = 0 (every node stays above it, up to the contact
  // tolerance), at the start: the bound on the kinetic energy.
  double potential = 0, mass = 0;
  for (int n = 0; n < model.num_nodes; ++n) {
    potential += model.node_mass[n] * -gravity.y() * world.state().x[3 * n + 1];
    mass += model.node_mass[n];
  }
  CHECK(mass > 10);  // the lattice's cells cover the 0.012 m^3 box and more, rho 1000
  double most_kinetic = 0;
  int steps = 0;
  for (; steps < 90; ++steps) {
    if (!world.step()) break;
    most_kinetic = std::max(most_kinetic, world.kinetic_energy());
  }
  INFO("kinetic energy at most " << most_kinetic << " J against " << potential << " J of potential energy");
  CHECK(steps == 90);
  CHECK(most_kinetic <= potential);
  // It did fall: a quarter of that energy at least became motion (mass damping takes part).
  CHECK(most_kinetic >= 0.25 * potential);
}
