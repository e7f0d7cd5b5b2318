// solve_velocity keeps the factorisation it holds when no element rotated since it was
// made: A depends on the positions only through the rotations, so a body that only
// translates (a fall) needs one factorisation, and one that turns needs one a step.
#include <doctest/doctest.h>

#include <string>

#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

const std::string kUnmoved = "no rotation moved since the last factorisation";

const std::string& factorize_skip(const World& w) {
  return w.profile().skipped[static_cast<int>(Stage::Factorize)];
}

}  // namespace

TEST_CASE("unmoved rotations: a falling cube factorises once, then lands and factorises again") {
  // Dropped from 0.5 m: about 19 steps of free fall before it reaches the plane.
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 0.5, "", 1e6, R"({"sleep_steps": 0})"));
  REQUIRE(w.model().solver.refactor_interval == 1);
  REQUIRE(w.step());
  CHECK(factorize_skip(w).empty());  // the first step has nothing to keep
  const double h = w.model().h;
  for (int k = 2; k <= 15; ++k) {
    REQUIRE(w.step());
    CHECK(factorize_skip(w) == kUnmoved);
    CHECK(w.state().factor_exact);
    // Backward Euler's free fall, v_k = -k h g on every node (K annihilates translations
    // whatever factor the step used; this checks that keeping it broke nothing).
    CHECK(mean_node_velocity(w).y() == doctest::Approx(-k * h * kGravity).epsilon(1e-12));
  }
  // Landing bends the cube's elements: their rotations move and each step factorises.
  int factorised_after_contact = 0, contact_steps = 0;
  for (int k = 16; k <= 60; ++k) {
    REQUIRE(w.step());
    if (w.state().rows.size() > 0) ++contact_steps;
    if (contact_steps > 0 && factorize_skip(w).empty()) ++factorised_after_contact;
  }
  REQUIRE(contact_steps > 10);
  CHECK(factorised_after_contact > 10);
}

TEST_CASE("unmoved rotations: a spinning cube factorises at every step") {
  // No gravity, far above the plane: only the spin moves the rotations.
  World w = make_world(box_scene(0.5, Vec3::Zero(), 5.0, "", 1e6, R"({"sleep_steps": 0})"));
  State& s = w.mutable_state();
  const Vec3 centre = mean_node_position(w), omega(0, 0.5, 0);  // rad/s: 0.008 rad a step
  for (int n = 0; n < w.model().num_nodes; ++n)
    s.v.segment<3>(3 * n) = omega.cross(Vec3(s.x.segment<3>(3 * n) - centre));
  for (int k = 0; k < 10; ++k) {
    REQUIRE(w.step());
    CHECK(factorize_skip(w).empty());
  }
}

TEST_CASE("unmoved rotations: a factorisation that must not be reused is not, rotations or not") {
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 0.5, "", 1e6, R"({"sleep_steps": 0})"));
  REQUIRE(w.step());
  REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);
  // What a retried step or a change of the sleeping set does (world.cpp): the next step factorises.
  w.mutable_state().factor_age = w.model().solver.refactor_interval;
  w.mutable_state().factor_rotations.clear();
  REQUIRE(w.step());
  CHECK(factorize_skip(w).empty());
  REQUIRE(w.step());
  CHECK(factorize_skip(w) == kUnmoved);
}
