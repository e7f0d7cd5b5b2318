// Newton on the incremental potential (hyperelastic bodies): convergence per step, and
// agreement with the linear corotational element at small strain.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "engine/world.hpp"

using namespace sinew;

namespace {

Model cantilever(const char* model, double rho, double h, double gravity, const char* elements = "hex") {
  char text[1024];
  std::snprintf(text, sizeof text, R"({"h": %.17g, "gravity": [0, %.17g, 0],
    "solver": {"newton_tolerance": 1e-8, "newton_max_iterations": 30},
    "bodies": [{"name": "beam", "shape": [{"type": "box", "half_extents": [0.5, 0.05, 0.05]}],
      "cell_size": 0.05, "elements": "%s", "material": {"model": "%s", "E": 1e6, "nu": 0.3, "rho": %.17g},
      "fixed": [{"half_space": {"point": [-0.49, 0, 0], "normal": [1, 0, 0]}}]}]})",
                h, gravity, elements, model, rho);
  return build_model(parse_scene_text(text, "cantilever", "."), [](const std::string&) {});
}

// Mean vertical displacement of the tip nodes after one static step (h = 1, tiny mass:
// backward Euler then solves the static equilibrium) under a total tip load P.
double static_tip_deflection(const char* model, double P) {
  World world(cantilever(model, 1e-9, 1.0, 0));
  std::vector<int> tip;
  for (int n = 0; n < world.model().num_nodes; ++n)
    if (world.model().rest_x[3 * n] > 0.5 - 1e-9) tip.push_back(n);
  for (int n : tip) world.mutable_state().external_force[3 * n + 1] = -P / tip.size();
  REQUIRE(world.step());
  double sum = 0;
  for (int n : tip) sum += world.state().x[3 * n + 1] - world.model().rest_x[3 * n + 1];
  return -sum / tip.size();
}

}  // namespace

TEST_CASE("Newton: every step of a hanging Stable Neo-Hookean beam converges to the tolerance") {
  World world(cantilever("stable_neo_hookean", 500, 1.0 / 60, -9.81));
  REQUIRE(world.model().has_hyperelastic);
  int worst_iterations = 0;
  for (int step = 0; step < 60; ++step) {
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    worst_iterations = std::max(worst_iterations, p.iterations.at("newton"));
    CHECK(p.violation.at("newton_residual") <= 1e-8);
  }
  MESSAGE("most Newton iterations in a step: " << worst_iterations);
  CHECK(worst_iterations < 30);
}

TEST_CASE("Newton: at small strain every hyperelastic model matches the linear corotational beam") {
  // Tip load giving a deflection of ~1e-4 of the length: strains ~1e-5, where every model
  // linearises to Hooke's law with the same Lame parameters (ARAP has no volume term and
  // is left out). The nonlinear terms are O(strain) relative, far below the 1e-3 asked.
  const double P = 1e-4;
  const double linear = static_tip_deflection("corotational", P);
  REQUIRE(linear > 0);
  for (const char* model : {"stable_neo_hookean", "neo_hookean", "corotational_hyperelastic", "stvk"}) {
    CAPTURE(model);
    const double d = static_tip_deflection(model, P);
    CHECK(std::abs(d - linear) / linear < 1e-3);
  }
}
