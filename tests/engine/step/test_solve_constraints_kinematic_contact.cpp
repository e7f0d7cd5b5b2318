// Kinematic obstacles through the whole step: a pushing plate, a pressing plate moved by
// keyframes, a moving table whose velocity friction must see.
#include <doctest/doctest.h>

#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

TEST_CASE("contact: a kinematic plate pushes a body along the ground and never tunnels") {
  // A plate (box obstacle) 2 cm left of the cube moving right at 0.5 m/s for 1.5 s.
  const std::string plate = R"(, {"type": "box", "half_extents": [0.02, 0.3, 0.3], "friction": 0.2,
      "motion": {"velocity": [0.5, 0, 0]}, "center": [-0.21, 0.2, 0]})";
  World w = make_world(box_scene(0.3, Vec3(0, -kGravity, 0), 1e-4, plate));
  const double tolerance = w.model().solver.contact_tolerance;
  const Vec3 start = mean_node_position(w);
  double deepest_plate = 0, deepest_ground = 0;
  for (int i = 0; i < 90; ++i) {
    REQUIRE(w.step());
    deepest_plate = std::max(deepest_plate, -lowest_phi(w, 1));
    deepest_ground = std::max(deepest_ground, -lowest_phi(w, 0));
  }
  const double pushed = mean_node_position(w).x() - start.x();
  MESSAGE("plate moved 0.75 m, body " << pushed << " m; deepest penetration: plate " << deepest_plate
                                      << " m, ground " << deepest_ground << " m");
  // The plate reaches the cube after ~0.04 s (2 cm gap at 0.5 m/s, minus the cube's own
  // 1 cm left overhang of the lattice mean): the body must follow for the rest, about 0.7 m.
  CHECK(pushed > 0.65);
  CHECK(pushed < 0.75);
  CHECK(deepest_plate <= tolerance);
  CHECK(deepest_ground <= tolerance);
}

TEST_CASE("contact: a plate moving by keyframes squeezes a body onto the ground without tunnelling") {
  // The plate comes down 6 cm onto the cube's top face (cube top at 0.34 m), holds, and lifts.
  const std::string plate = R"(, {"type": "box", "half_extents": [0.4, 0.05, 0.4], "friction": 0.5,
      "motion": {"keyframes": [{"t": 0, "position": [0, 0.40, 0]}, {"t": 0.5, "position": [0, 0.34, 0]},
                               {"t": 1.0, "position": [0, 0.34, 0]}, {"t": 1.5, "position": [0, 0.6, 0]}]}})";
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 1e-4, plate, 2e5));
  const double tolerance = w.model().solver.contact_tolerance;
  double deepest_plate = 0, deepest_ground = 0, squeezed = 0;
  for (int i = 0; i < 120; ++i) {
    REQUIRE(w.step());
    deepest_plate = std::max(deepest_plate, -lowest_phi(w, 1));
    deepest_ground = std::max(deepest_ground, -lowest_phi(w, 0));
    double top = -1e300;
    for (const Vec3& p : w.state().surface[0]) top = std::max(top, p.y());
    squeezed = std::max(squeezed, 0.34 + 1e-4 - top);
  }
  MESSAGE("largest squeeze of the cube's height " << squeezed << " m; deepest penetration: plate "
                                                  << deepest_plate << " m, ground " << deepest_ground << " m");
  CHECK(squeezed > 0.04);  // the plate bottom reaches 0.29 m: the 0.34 m cube is squeezed ~5 cm
  CHECK(deepest_plate <= tolerance);
  CHECK(deepest_ground <= tolerance);
}

TEST_CASE("contact: a moving table carries a box along by friction") {
  // The plane slides along x at 1 m/s (its distance field does not change, only its velocity).
  // Kinetic friction accelerates the box at mu g = 4.9 m/s^2 until it moves with the table.
  SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 1e-4);
  scene.obstacles[0].motion.velocity = Vec3(1, 0, 0);
  World w = make_world(scene);
  for (int i = 0; i < 6; ++i) REQUIRE(w.step());
  const double early = mean_node_velocity(w).x();  // after 0.1 s: mu g t = 0.49 m/s
  for (int i = 0; i < 54; ++i) REQUIRE(w.step());
  const double late = mean_node_velocity(w).x();
  MESSAGE("box velocity after 0.1 s " << early << " m/s (mu g t = " << 0.5 * kGravity * 0.1 << "), after 1 s "
                                      << late << " m/s");
  CHECK(early == doctest::Approx(0.5 * kGravity * 0.1).epsilon(0.05));
  CHECK(late == doctest::Approx(1.0).epsilon(0.01));
}
