// Live parameter edits: validated like the scene file, applied by rebuilding the model with
// the state carried over.
#include <doctest/doctest.h>

#include "engine/core/error.hpp"
#include "ui/live_scene.hpp"

using namespace sinew;

namespace {

SceneDesc box_scene() {
  return parse_scene_text(R"({"gravity": [0, -9.81, 0], "bodies": [{"name": "b",
      "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
      "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})", "t", ".");
}

}  // namespace

TEST_CASE("live scene: a new E rebuilds the engine and keeps the motion") {
  LiveScene live(box_scene());
  for (int s = 0; s < 5; ++s) REQUIRE(live.world().step());
  const VecX x = live.world().state().x, v = live.world().state().v;
  const double t = live.world().state().t;
  live.set_parameter("E", 2e6);
  CHECK(live.world().model().bodies[0].material.E == 2e6);
  CHECK(live.parameter("E") == 2e6);
  CHECK(live.world().state().x == x);
  CHECK(live.world().state().v == v);
  CHECK(live.world().state().t == t);
  live.reset();
  CHECK(live.world().state().t == 0);
  CHECK(live.parameter("E") == 2e6);  // reset keeps the edits
}

TEST_CASE("live scene: bad edits are refused and change nothing") {
  LiveScene live(box_scene());
  CHECK_THROWS_WITH_AS(live.set_parameter("nu", 0.5), "parameter 'nu' must be a number in [0, 0.5), got 0.500000",
                       InputError);
  CHECK_THROWS_WITH_AS(live.set_parameter("stiffness", 1), "unknown parameter 'stiffness'", InputError);
  CHECK_THROWS_WITH_AS(live.set_parameter("pgs_max_iterations", 2.5),
                       "parameter 'pgs_max_iterations' must be a whole number >= 1, got 2.500000", InputError);
  CHECK_THROWS_AS(live.set_material_model("jelly"), InputError);
  // Strain limits need tet elements: the model refuses, the scene stays as it was.
  CHECK_THROWS_AS(live.set_parameter("smax.x", 1.1), InputError);
  CHECK(!live.scene().bodies[0].strain_limit.enabled);
  CHECK(live.parameter("nu") == 0.3);
  CHECK_THROWS_AS(live.select_body("nobody"), InputError);
}
