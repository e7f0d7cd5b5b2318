// Driven regions (docs/scenes.md, `driven`): parsing, rejection on linear bodies, and the
// prescribed motion DrivenNodes::position.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "engine/core/error.hpp"
#include "engine/model.hpp"

using namespace sinew;

namespace {

std::string bar(const std::string& model, const std::string& extra) {
  return R"({"gravity": [0, 0, 0], "bodies": [{"shape": [{"type": "box", "half_extents": [0.5, 0.1, 0.1]}],
    "cell_size": 0.1, "material": {"model": ")" + model + R"(", "E": 1e5, "nu": 0.3, "rho": 100},
    "fixed": [{"half_space": {"point": [-0.45, 0, 0], "normal": [1, 0, 0]}}], )" + extra + "}]}";
}

const std::string kDriven =
    R"("driven": [{"half_space": {"point": [0.45, 0, 0], "normal": [-1, 0, 0]},
        "rotate": {"axis": [0, 0, 2], "pivot": [0.5, 0, 0], "degrees": 90, "duration": 2}}])";

}  // namespace

TEST_CASE("driven: parsed, normalised axis, nodes leave the unknowns") {
  const SceneDesc scene = parse_scene_text(bar("stable_neo_hookean", kDriven), "bar", ".");
  REQUIRE(scene.bodies[0].driven.size() == 1);
  CHECK(scene.bodies[0].driven[0].axis.isApprox(Vec3::UnitZ()));
  const Model model = build_model(scene, [](const std::string&) {});
  REQUIRE(model.driven.size() == 1);
  for (int n : model.driven[0].nodes) {
    CHECK(model.free_index[n] == -1);
    CHECK(model.rest_x[3 * n] >= 0.45);
  }
}

TEST_CASE("driven: a linear corotational body is rejected with the reason") {
  try {
    parse_scene_text(bar("corotational", kDriven), "bar", ".");
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("bodies[0].driven") != std::string::npos);
    CHECK(what.find("hyperelastic") != std::string::npos);
  }
}

TEST_CASE("driven: overlapping a fixed region or holding no node is an error") {
  const std::string overlap = R"("driven": [{"half_space": {"point": [0, 0, 0], "normal": [1, 0, 0]},
      "rotate": {"axis": [0, 0, 1], "pivot": [0, 0, 0], "degrees": 10}}])";
  CHECK_THROWS_AS(build_model(parse_scene_text(bar("stable_neo_hookean", overlap), "bar", "."), [](const std::string&) {}),
                  InputError);
  const std::string empty = R"("driven": [{"box": {"min": [5, 5, 5], "max": [6, 6, 6]},
      "rotate": {"axis": [0, 0, 1], "pivot": [0, 0, 0], "degrees": 10}}])";
  CHECK_THROWS_AS(build_model(parse_scene_text(bar("stable_neo_hookean", empty), "bar", "."), [](const std::string&) {}),
                  InputError);
}

TEST_CASE("driven: the motion is a smoothstep-ramped rotation about the pivot, then held") {
  DrivenNodes d;
  d.axis = Vec3::UnitZ();
  d.pivot = Vec3(1, 0, 0);
  d.radians = std::numbers::pi / 2;
  d.duration = 2;
  const Vec3 rest(2, 0, 0);
  CHECK((d.position(rest, 0) - rest).norm() < 1e-15);
  // Half way: s(1/2) = 1/2, so 45 degrees.
  const double c = std::sqrt(0.5);
  CHECK((d.position(rest, 1) - Vec3(1 + c, c, 0)).norm() < 1e-14);
  CHECK((d.position(rest, 2) - Vec3(1, 1, 0)).norm() < 1e-14);
  CHECK((d.position(rest, 5) - Vec3(1, 1, 0)).norm() < 1e-14);
  // Distances to the pivot are kept (rigid).
  CHECK(std::abs((d.position(rest, 0.7) - d.pivot).norm() - 1) < 1e-14);
}
