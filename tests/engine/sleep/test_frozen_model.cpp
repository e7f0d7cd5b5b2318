// freeze_sleeping_bodies (engine/sleep/frozen_model.cpp): a sleeper's nodes leave the
// unknowns, its elements the colours and its limits the rows; awake bodies are untouched.
#include <doctest/doctest.h>

#include "engine/sleep/sleep.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

Model two_bodies() {
  const SceneDesc scene = parse_scene_text(R"({"bodies": [
      {"name": "a", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
       "material": {"E": 1e5, "nu": 0.3, "rho": 500}, "energy_limit": {"Umax": 1},
       "fixed": [{"half_space": {"point": [-0.15, 0, 0], "normal": [1, 0, 0]}}]},
      {"name": "b", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}], "cell_size": 0.1, "elements": "tet",
       "transform": {"translate": [1, 0, 0]}, "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.3, "rho": 500},
       "strain_limit": {"smin": [0.9, 0.9, 0.9], "smax": [1.1, 1.1, 1.1]}}]})",
                                           "two", ".");
  return build_model(scene, [](const std::string&) {});
}

}  // namespace

TEST_CASE("frozen model: a sleeping body's nodes are fixed, its elements and limits gone") {
  const Model full = two_bodies();
  REQUIRE(full.has_hyperelastic);
  REQUIRE(full.has_strain_limits);
  const Body& b = full.bodies[1];
  const Model frozen = freeze_sleeping_bodies(full, {0, 1});
  CHECK(frozen.asleep(1));
  CHECK_FALSE(frozen.asleep(0));
  CHECK_FALSE(full.asleep(1));
  CHECK(frozen.num_free == full.num_free - b.num_nodes());
  for (int n = 0; n < full.num_nodes; ++n)
    CHECK(frozen.free_index[n] == (full.node_body[n] == 1 ? -1 : full.free_index[n]));  // body a: numbering kept
  long colored = 0;
  for (const auto& color : frozen.element_colors)
    for (int e : color) {
      CHECK(frozen.element_body[e] == 0);
      ++colored;
    }
  CHECK(colored == full.bodies[0].num_elements());
  long scheduled = 0;
  for (const auto& color : frozen.element_schedule.colors)
    for (const ElementBlock& block : color)
      for (int e = block.first; e < block.last; ++e) {
        CHECK(frozen.element_body[e] == 0);
        ++scheduled;
      }
  CHECK(scheduled == full.bodies[0].num_elements());
  CHECK_FALSE(frozen.has_hyperelastic);
  CHECK_FALSE(frozen.has_strain_limits);
  CHECK(frozen.pattern.matrix.rows() == 3 * frozen.num_free);
  for (int e = 0; e < full.num_elements; ++e) CHECK(frozen.element_Umax[e] == full.element_Umax[e]);  // b has none
}

TEST_CASE("frozen model: the awake body's nodes are renumbered after a sleeper's") {
  const Model full = two_bodies();
  const Model frozen = freeze_sleeping_bodies(full, {1, 0});
  const Body& b = full.bodies[1];
  CHECK(frozen.num_free == b.num_nodes());
  for (int n = 0; n < b.num_nodes(); ++n) CHECK(frozen.free_index[b.node_offset + n] == n);
  for (int e = 0; e < full.num_elements; ++e)
    if (full.element_body[e] == 0) CHECK(frozen.element_Umax[e] == 0);
  CHECK(frozen.has_hyperelastic);
  CHECK(frozen.has_strain_limits);
}
