// body_disturbed (engine/sleep/disturbance.cpp): what will move a body during a step.
#include <doctest/doctest.h>

#include "engine/sleep/sleep.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

// A 0.2 m box of the given material model, 0.1 s steps.
Model box_with(const std::string& extra_body_keys, const std::string& obstacles, const std::string& model = "corotational") {
  const std::string text = R"({"h": 0.1, "bodies": [{"name": "box", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}],
      "cell_size": 0.1, "material": {"model": ")" + model + R"(", "E": 1e5, "nu": 0.3, "rho": 500})" + extra_body_keys + R"(}],
      "obstacles": [)" + obstacles + "]}";
  return build_model(parse_scene_text(text, "box", "."), [](const std::string&) {});
}

Aabb bounds_of(const Model& m) {
  Aabb box;
  for (int n = 0; n < m.num_nodes; ++n) box.extend(m.rest_x.segment<3>(3 * n));
  return box;
}

}  // namespace

TEST_CASE("disturbance: a ramping load, until its ramp ends") {
  const Model m = box_with(R"(, "loads": [{"box": {"min": [-1, -1, -1], "max": [1, 1, 1]}, "force": [0, 1, 0], "ramp_time": 0.5}])", "");
  CHECK(body_disturbed(m, 0, 0.0, bounds_of(m)));
  CHECK(body_disturbed(m, 0, 0.35, bounds_of(m)));
  CHECK_FALSE(body_disturbed(m, 0, 0.5, bounds_of(m)));
  CHECK_FALSE(body_disturbed(m, 0, 3.0, bounds_of(m)));
}

TEST_CASE("disturbance: driven nodes, while their motion lasts") {
  const Model m = box_with(R"(, "driven": [{"half_space": {"point": [0.09, 0, 0], "normal": [-1, 0, 0]},
      "rotate": {"axis": [0, 0, 1], "pivot": [0, 0, 0], "degrees": 30, "duration": 1}}])", "",
                           "stable_neo_hookean");
  CHECK(body_disturbed(m, 0, 0.0, bounds_of(m)));
  CHECK(body_disturbed(m, 0, 0.85, bounds_of(m)));
  CHECK_FALSE(body_disturbed(m, 0, 1.0, bounds_of(m)));
}

TEST_CASE("disturbance: a moving obstacle near the body; not a still or a distant one") {
  const std::string still = R"({"type": "sphere", "radius": 0.1, "center": [0.25, 0, 0]})";
  const std::string moving_near = R"({"type": "sphere", "radius": 0.1, "motion": {"keyframes": [
      {"t": 0, "position": [1.0, 0, 0]}, {"t": 1, "position": [0.2, 0, 0]}]}})";
  const std::string moving_far = R"({"type": "sphere", "radius": 0.1, "motion": {"velocity": [0, 0, 1]}, "center": [3, 0, 0]})";
  const Model a = box_with("", still), b = box_with("", moving_near), c = box_with("", moving_far);
  CHECK_FALSE(body_disturbed(a, 0, 0.5, bounds_of(a)));
  CHECK_FALSE(body_disturbed(b, 0, 0.0, bounds_of(b)));  // still 0.8 m away at the end of the step
  CHECK(body_disturbed(b, 0, 0.9, bounds_of(b)));        // ends the step touching the box
  CHECK_FALSE(body_disturbed(b, 0, 1.5, bounds_of(b)));  // keyframes over: it no longer moves
  CHECK_FALSE(body_disturbed(c, 0, 0.5, bounds_of(c)));
}
