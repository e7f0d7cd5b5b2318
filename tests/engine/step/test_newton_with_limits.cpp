// A Stable Neo-Hookean body whose energy limits are active: Newton still converges in a few
// iterations per step. Regression (tools/stress): the previous step's constraint curvature
// entered Newton's matrix but not its gradient, and every step ran to the cap (20) with a
// residual near 1e-2.
#include <doctest/doctest.h>

#include "engine/world.hpp"

using namespace sinew;

TEST_CASE("solve_newton: converges with active energy-limit rows") {
  const std::string text = R"({"bodies": [{"name": "snh", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}],
      "cell_size": 0.1, "elements": "tet", "surface_resolution": 0.09, "transform": {"translate": [0.5, 0.1001, 0]},
      "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"mass": 2},
      "energy_limit": {"Umax": 1e-4}}],
    "obstacles": [{"type": "plane", "friction": 0.5}]})";
  World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
  for (int s = 0; s < 10; ++s) {
    CAPTURE(s);
    REQUIRE(world.step());
    CHECK(world.profile().rows.count("energy"));  // the limits bind on every step
    CHECK(world.profile().iterations.at("newton") < world.model().solver.newton_max_iterations);
    CHECK(world.profile().violation.at("newton_residual") <= world.model().solver.newton_tolerance);
  }
}
