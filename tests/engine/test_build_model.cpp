#include <doctest/doctest.h>

#include "engine/core/error.hpp"
#include "engine/model.hpp"
#include "tests/engine/assembly/element_schedule_check.hpp"

using namespace sinew;

namespace {
SceneDesc two_bodies() {
  return parse_scene_text(R"({"bodies": [
    {"name": "a", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
     "material": {"E": 1e5, "nu": 0.3, "rho": 1000},
     "fixed": [{"half_space": {"point": [-0.15, 0, 0], "normal": [1, 0, 0]}}]},
    {"name": "b", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1], "center": [0, 1, 0]}],
     "cell_size": 0.1, "material": {"E": 2e5, "nu": 0.3, "rho": 500},
     "energy_limit": {"Umax": 2, "regions": [{"box": {"min": [-1, 0.95, -1], "max": [0, 2, 1]}, "Umax": 0.5}]}}]})",
                          "two", ".");
}
}  // namespace

TEST_CASE("build_model: masses, fixed nodes, offsets, colours and energy-limit regions") {
  const Model m = build_model(two_bodies(), [](const std::string&) {});
  REQUIRE(m.bodies.size() == 2);
  CHECK(m.bodies[0].num_elements() == 4 * 2 * 2);
  CHECK(m.bodies[1].num_elements() == 2 * 2 * 2);
  CHECK(m.bodies[1].node_offset == m.bodies[0].num_nodes());
  // Lumped mass sums to rho * volume per body.
  double mass_a = 0, mass_b = 0;
  for (int n = 0; n < m.num_nodes; ++n) (m.node_body[n] == 0 ? mass_a : mass_b) += m.node_mass[n];
  CHECK(mass_a == doctest::Approx(1000 * 0.4 * 0.2 * 0.2));
  CHECK(mass_b == doctest::Approx(500 * 0.2 * 0.2 * 0.2));
  // The half-space x <= -0.15 holds the 9 nodes of body a's face at x = -0.2.
  int fixed = 0;
  for (int n = 0; n < m.num_nodes; ++n) fixed += m.free_index[n] < 0;
  CHECK(fixed == 9);
  CHECK(m.num_free == m.num_nodes - 9);
  // Colours: no two elements of a colour share a node.
  int total = 0;
  for (const auto& colour : m.element_colors) {
    std::vector<int> seen(m.num_nodes, 0);
    for (int e : colour)
      for (int n : m.element_nodes[e]) CHECK(++seen[n] == 1);
    total += static_cast<int>(colour.size());
  }
  CHECK(total == m.num_elements);
  check_element_schedule(m);
  // Energy limits: body a none, body b 2 J except the region (x < 0) at 0.5 J.
  for (int e = 0; e < m.num_elements; ++e) {
    if (m.element_body[e] == 0) {
      CHECK(m.element_Umax[e] == 0);
      continue;
    }
    Vec3 centre = Vec3::Zero();
    for (int n : m.element_nodes[e]) centre += m.rest_x.segment<3>(3 * n) / 8;
    CHECK(m.element_Umax[e] == (centre.x() < 0 ? 0.5 : 2.0));
  }
  // Same cell size, different E: two element references.
  CHECK(m.references.size() == 2);
}

TEST_CASE("build_model: a body with no geometry is an input error naming its JSON path") {
  SceneDesc scene = two_bodies();
  scene.path = "scene.json";
  scene.bodies[1].shape.parts.clear();
  try {
    build_model(scene, [](const std::string&) {});
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("scene.json: bodies[1].shape") != std::string::npos);
    CHECK(what.find("empty") != std::string::npos);
  }
}
