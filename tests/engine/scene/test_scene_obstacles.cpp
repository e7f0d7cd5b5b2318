// Obstacle and contact-setting part of the scene parser (engine/scene/scene_parser.cpp):
// each obstacle type, kinematic motion, and the error messages with JSON paths.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/scene/scene.hpp"

using nlohmann::json;
using namespace sinew;

namespace {

json scene_with(const json& obstacles) {
  json scene = json::parse(R"({"bodies": [{"shape": [{"type": "sphere", "radius": 0.2}],
    "cell_size": 0.1, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})");
  scene["obstacles"] = obstacles;
  return scene;
}

SceneDesc parse(const json& scene) { return parse_scene_text(scene.dump(), "test.json", ""); }

std::string error_of(const json& scene) {
  try {
    parse(scene);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void check_error(const json& scene, const std::string& expected) {
  const std::string message = error_of(scene);
  INFO("message: " << message);
  CHECK(message == "test.json: " + expected);
}

}  // namespace

TEST_CASE("scene obstacles: every type with its keys") {
  const SceneDesc s = parse(scene_with(json::parse(R"([
    {"type": "plane", "point": [0, -1, 0], "normal": [0, 0, 2]},
    {"type": "box", "center": [1, 2, 3], "half_extents": [0.1, 0.2, 0.3], "rotation_deg": [0, 0, 90], "friction": 0.2},
    {"type": "sphere", "center": [0, 1, 0], "radius": 0.4},
    {"type": "capsule", "radius": 0.1, "length": 0.6, "friction": 0}])")));
  REQUIRE(s.obstacles.size() == 4);
  CHECK(s.obstacles[0].kind == ObstacleDesc::Kind::Plane);
  CHECK((s.obstacles[0].normal - Vec3(0, 0, 1)).norm() < 1e-15);
  CHECK(s.obstacles[1].kind == ObstacleDesc::Kind::Box);
  CHECK((s.obstacles[1].point - Vec3(1, 2, 3)).norm() == 0);
  CHECK((s.obstacles[1].half_extents - Vec3(0.1, 0.2, 0.3)).norm() == 0);
  CHECK((s.obstacles[1].rotation * Vec3::UnitX() - Vec3::UnitY()).norm() < 1e-15);  // 90 deg about z
  CHECK(s.obstacles[1].friction == 0.2);
  CHECK(s.obstacles[2].kind == ObstacleDesc::Kind::Sphere);
  CHECK(s.obstacles[2].radius == 0.4);
  CHECK(s.obstacles[3].kind == ObstacleDesc::Kind::Capsule);
  CHECK(s.obstacles[3].half_length == doctest::Approx(0.3));
  CHECK(s.obstacles[3].friction == 0);
  for (const ObstacleDesc& ob : s.obstacles) CHECK(ob.motion.keyframes.empty());
  CHECK(s.solver.contact_tolerance == 1e-4);
  CHECK(s.solver.contact_margin < 0);  // automatic: a quarter of the cell size
}

TEST_CASE("scene obstacles: motion by velocity or keyframes") {
  const SceneDesc s = parse(scene_with(json::parse(R"([
    {"type": "plane", "motion": {"velocity": [1, 0, 0]}},
    {"type": "box", "half_extents": [1, 1, 1],
     "motion": {"keyframes": [{"t": 0, "position": [0, 1, 0]}, {"t": 2, "position": [0, 0, 0]}]}}])")));
  CHECK((s.obstacles[0].motion.velocity - Vec3(1, 0, 0)).norm() == 0);
  REQUIRE(s.obstacles[1].motion.keyframes.size() == 2);
  CHECK(s.obstacles[1].motion.keyframes[1].t == 2);
  CHECK((s.obstacles[1].point - Vec3(0, 1, 0)).norm() == 0);  // the first keyframe
}

TEST_CASE("scene obstacles: errors name the JSON path") {
  check_error(scene_with({{{"type", "box"}}}), "obstacles[0]: missing required key 'half_extents'");
  check_error(scene_with({{{"type", "sphere"}, {"radius", 0}}}),
              "obstacles[0].radius: expected a number > 0, got 0");
  check_error(scene_with({{{"type", "capsule"}, {"radius", 1}, {"length", -1}}}),
              "obstacles[0].length: expected a number >= 0, got -1");
  // Keys of another type are rejected, with a suggestion when one is close.
  check_error(scene_with({{{"type", "sphere"}, {"radius", 1}, {"normal", {0, 1, 0}}}}),
              "obstacles[0].normal: unknown key 'normal' (expected one of: 'type', 'friction', "
              "'motion', 'center', 'radius')");
  check_error(scene_with({{{"type", "sphere"}, {"radius", 1}, {"centre", {0, 1, 0}}}}),
              "obstacles[0].centre: unknown key 'centre' (did you mean 'center'?)");
  check_error(scene_with({{{"type", "plane"}, {"center", {0, 1, 0}}}}),
              "obstacles[0].center: unknown key 'center' (expected one of: 'type', 'friction', "
              "'motion', 'point', 'normal')");

  check_error(scene_with({{{"motion", json::object()}}}),
              "obstacles[0].motion: expected exactly one of 'velocity' or 'keyframes', got neither");
  check_error(scene_with({{{"motion", {{"velocity", {1, 0}}}}}}),
              "obstacles[0].motion.velocity: expected an array of 3 numbers, got [1,0]");
  check_error(scene_with({{{"motion", {{"keyframes", json::array()}}}}}),
              "obstacles[0].motion.keyframes: expected a non-empty array, got []");
  check_error(scene_with({{{"motion", {{"keyframes", {{{"t", 0}}}}}}}}),
              "obstacles[0].motion.keyframes[0]: missing required key 'position'");
  check_error(scene_with(json::parse(R"([{"motion": {"keyframes": [{"t": 1, "position": [0, 0, 0]},
                                          {"t": 1, "position": [0, 1, 0]}]}}])")),
              "obstacles[0].motion.keyframes[1].t: expected a time greater than the previous "
              "keyframe's (1), got 1");
  check_error(scene_with(json::parse(R"([{"motion": {"keyframes": [{"t": 0, "positon": [0, 0, 0]}]}}])")),
              "obstacles[0].motion.keyframes[0].positon: unknown key 'positon' (did you mean 'position'?)");
  check_error(scene_with(json::parse(R"([{"point": [0, 1, 0], "motion": {"keyframes": [{"t": 0, "position": [0, 0, 0]}]}}])")),
              "obstacles[0].point: not allowed with 'motion.keyframes' (the keyframes give the point at "
              "every time)");
}

TEST_CASE("scene obstacles: contact settings under solver") {
  json scene = scene_with(json::array());
  CHECK(parse(scene).solver.body_friction == 0.5);
  scene["solver"] = {{"contact_tolerance", 1e-3}, {"contact_margin", 0}, {"body_friction", 0.2}};
  const SceneDesc s = parse(scene);
  CHECK(s.solver.contact_tolerance == 1e-3);
  CHECK(s.solver.contact_margin == 0);
  CHECK(s.solver.body_friction == 0.2);
  scene["solver"] = {{"body_friction", -1}};
  check_error(scene, "solver.body_friction: expected a number >= 0, got -1");
  scene["solver"] = {{"contact_tolerance", 0}};
  check_error(scene, "solver.contact_tolerance: expected a number > 0, got 0");
  scene["solver"] = {{"contact_margin", -1}};
  check_error(scene, "solver.contact_margin: expected a number >= 0, got -1");
  scene["solver"] = {{"contact_margn", 1}};
  check_error(scene, "solver.contact_margn: unknown key 'contact_margn' (did you mean 'contact_margin'?)");
}

TEST_CASE("scene obstacles: a mesh obstacle resolves its OBJ path; errors name it") {
  check_error(scene_with({{{"type", "mesh"}}}), "obstacles[0]: missing required key 'mesh'");
  const std::string message = error_of(scene_with({{{"type", "mesh"}, {"mesh", "no_such.obj"}}}));
  CHECK(message.find("test.json: obstacles[0].mesh: mesh file 'no_such.obj' not found") == 0);
  check_error(scene_with({{{"type", "mesh"}, {"mesh", "x.obj"}, {"scale", 0}}}),
              "obstacles[0].mesh: mesh file 'x.obj' not found (resolved to '" +
                  std::filesystem::absolute("x.obj").lexically_normal().string() + "')");
  const std::string obj = std::string(SINEW_SOURCE_DIR) + "/tests/engine/scene/test_scene_obstacles.cpp";
  const SceneDesc s = parse(scene_with({{{"type", "mesh"}, {"mesh", obj}, {"scale", 2}, {"center", {0, 1, 0}}}}));
  CHECK(s.obstacles[0].kind == ObstacleDesc::Kind::Mesh);
  CHECK(s.obstacles[0].mesh_path == obj);
  CHECK(s.obstacles[0].scale == 2);
  CHECK(!s.obstacles[0].mesh);  // loaded by build_model, not by the parser
}
