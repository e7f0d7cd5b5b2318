// freeze_sleeping_bodies (engine/sleep/frozen_model.cpp): a sleeper's nodes leave the
// unknowns, its elements the colours and its limits the rows; awake bodies are untouched.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/assembly/element_kernels.hpp"
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

// Newton's residual floor (solve_newton.cpp) sums the awake hyperelastic bodies only: a large
// stiff sleeper would otherwise raise a small awake body's floor, and Newton would stop early.
TEST_CASE("frozen model: Newton's unit-strain force scale counts awake hyperelastic bodies only") {
  const SceneDesc scene = parse_scene_text(R"({"bodies": [
      {"name": "stiff", "shape": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}], "cell_size": 0.25, "elements": "tet",
       "material": {"model": "stable_neo_hookean", "E": 1e8, "nu": 0.3, "rho": 500}},
      {"name": "soft", "shape": [{"type": "box", "half_extents": [0.05, 0.05, 0.05]}], "cell_size": 0.05, "elements": "tet",
       "transform": {"translate": [2, 0, 0]}, "material": {"model": "stable_neo_hookean", "E": 1e4, "nu": 0.3, "rho": 500}},
      {"name": "linear", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}], "cell_size": 0.1,
       "transform": {"translate": [-2, 0, 0]}, "material": {"E": 1e5, "nu": 0.3, "rho": 500}}]})",
                                           "three", ".");
  const Model full = build_model(scene, [](const std::string&) {});
  const double stiff2 = full.bodies[0].unit_strain_forces2, soft2 = full.bodies[1].unit_strain_forces2;
  REQUIRE(stiff2 > 0);
  REQUIRE(soft2 > 0);
  CHECK(full.bodies[2].unit_strain_forces2 == 0);  // linear: not in Newton's scale
  // Per body, (2 mu_L + lambda_L) V^(2/3) per element: E 1e4 Pa, nu 0.3 gives 2 mu + lambda =
  // E (1 - nu) / ((1 + nu)(1 - 2 nu)).
  const double k = 1e4 * 0.7 / (1.3 * 0.4);
  double sum2 = 0;
  for (int e = full.bodies[1].element_offset; e < full.bodies[1].element_offset + full.bodies[1].num_elements(); ++e) {
    const double v = element_rest_volume(full, e);
    sum2 += std::pow(k * std::cbrt(v * v), 2);
  }
  CHECK(soft2 == doctest::Approx(sum2).epsilon(1e-12));
  CHECK(full.hyperelastic_unit_strain_forces == doctest::Approx(std::sqrt(stiff2 + soft2)).epsilon(1e-15));
  const Model frozen = freeze_sleeping_bodies(full, {1, 0, 0});  // the stiff body asleep
  CHECK(frozen.hyperelastic_unit_strain_forces == doctest::Approx(std::sqrt(soft2)).epsilon(1e-15));
  CHECK(freeze_sleeping_bodies(full, {1, 1, 0}).hyperelastic_unit_strain_forces == 0);
}
