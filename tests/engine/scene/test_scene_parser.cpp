#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/scene/scene.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using sinew::InputError;
using sinew::PrimitiveKind;
using sinew::RegionDesc;
using sinew::SceneDesc;
using sinew::Vec3;

namespace {

fs::path scene_test_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() /
               ("sinew_test_scene_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

const char* const kTetraObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

// The smallest valid scene: one box body.
json minimal_scene() {
  return json::parse(R"({
    "bodies": [ {
      "shape": [ {"type": "box", "half_extents": [0.5, 0.1, 0.1]} ],
      "cell_size": 0.05,
      "material": {"E": 1e5, "nu": 0.3, "rho": 1000}
    } ]
  })");
}

// Message of the InputError that parsing `text` throws ("" if it parses).
std::string error_of_text(const std::string& text, const std::string& base_dir = "") {
  try {
    sinew::parse_scene_text(text, "test.json", base_dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string error_of(const json& scene, const std::string& base_dir = "") {
  return error_of_text(scene.dump(2), base_dir);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The error names the file and path, then `expected` (which starts with the path).
void check_error(const json& scene, const std::string& expected) {
  const std::string message = error_of(scene);
  INFO("message: ", message);
  CHECK(contains(message, "test.json: " + expected));
}

SceneDesc parse(const json& scene, const std::string& base_dir = "") {
  return sinew::parse_scene_text(scene.dump(), "test.json", base_dir);
}

bool near(const Vec3& a, const Vec3& b) { return (a - b).norm() < 1e-12; }

}  // namespace

TEST_CASE("scene parser: a full scene round-trips into SceneDesc") {
  const fs::path dir = scene_test_dir("full");
  write_file(dir / "meshes" / "tet.obj", kTetraObj);
  write_file(dir / "beam.json", R"({
    "name": "beam test",
    "gravity": [0, 0, -9.8], "h": 0.004, "fps": 50, "frames": 30,
    "solver": {"linear": "pcg", "pcg_tolerance": 1e-6, "pcg_max_iterations": 300,
               "pgs_max_iterations": 50, "pgs_tolerance": 1e-4, "sqp_max_iterations": 4,
               "sqp_tolerance": 0.01, "activation_margin": 0.1},
    "bodies": [
      { "name": "beam",
        "shape": [ {"type": "box", "half_extents": [0.5, 0.1, 0.2], "center": [1, 2, 3],
                    "rotation_deg": [0, 0, 90]},
                   {"type": "sphere", "radius": 0.3},
                   {"type": "cylinder", "radius": 0.1, "length": 0.8},
                   {"type": "capsule", "radius": 0.05, "length": 0.4},
                   {"type": "ellipsoid", "semi_axes": [0.1, 0.2, 0.3]} ],
        "transform": {"scale": 2, "rotation_deg": [90, 0, 0], "translate": [0, 1, 0]},
        "cell_size": 0.1, "surface_resolution": 0.02,
        "material": {"model": "corotational", "E": 1.5e5, "nu": 0.25, "rho": 500},
        "damping": {"mass": 0.1, "stiffness": 0.01},
        "fixed": [ {"box": {"min": [-1, -1, -1], "max": [-0.4, 1, 1]}},
                   {"half_space": {"point": [0, 0, 0], "normal": [0, 0, -3]}} ],
        "velocity": [1, 0, 0],
        "energy_limit": {"Umax": 0.5, "jacobian": "warped",
                         "regions": [ {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "Umax": 0.2} ]}
      },
      { "mesh": "meshes/tet.obj", "cell_size": 0.2,
        "material": {"E": 2e6, "nu": 0, "rho": 1200} }
    ],
    "obstacles": [ {"type": "plane", "point": [0, -1, 0], "normal": [0, 2, 0], "friction": 0.8},
                   {} ]
  })");

  // Loaded from another working directory, so the mesh must resolve against the file's folder.
  const fs::path old_cwd = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  const SceneDesc s = sinew::load_scene((dir / "beam.json").string());
  fs::current_path(old_cwd);

  CHECK(s.path == (dir / "beam.json").string());
  CHECK(s.name == "beam test");
  CHECK(near(s.gravity, Vec3(0, 0, -9.8)));
  CHECK(s.h == 0.004);
  CHECK(s.fps == 50);
  CHECK(s.frames == 30);
  CHECK(s.steps_per_frame() == 5);
  CHECK(s.solver.linear == "pcg");
  CHECK(s.solver.pcg_tolerance == 1e-6);
  CHECK(s.solver.pcg_max_iterations == 300);
  CHECK(s.solver.pgs_max_iterations == 50);
  CHECK(s.solver.pgs_tolerance == 1e-4);
  CHECK(s.solver.sqp_max_iterations == 4);
  CHECK(s.solver.sqp_tolerance == 0.01);
  CHECK(s.solver.activation_margin == 0.1);

  REQUIRE(s.bodies.size() == 2);
  const sinew::BodyDesc& b = s.bodies[0];
  CHECK(b.json_path == "bodies[0]");
  CHECK(b.name == "beam");
  CHECK(b.mesh_path.empty());
  REQUIRE(b.shape.parts.size() == 5);
  const auto& parts = b.shape.parts;
  CHECK(parts[0].kind == PrimitiveKind::Box);
  CHECK(near(parts[0].size, Vec3(0.5, 0.1, 0.2)));
  CHECK(near(parts[0].center, Vec3(1, 2, 3)));
  CHECK(near(parts[0].rotation * Vec3::UnitX(), Vec3::UnitY()));  // 90 degrees about z
  CHECK(parts[1].kind == PrimitiveKind::Sphere);
  CHECK(parts[1].size.x() == 0.3);
  CHECK(near(parts[1].center, Vec3::Zero()));
  CHECK(parts[1].rotation.isIdentity());
  CHECK(parts[2].kind == PrimitiveKind::Cylinder);
  CHECK(parts[2].size.x() == 0.1);
  CHECK(parts[2].size.y() == doctest::Approx(0.4));  // half length
  CHECK(parts[3].kind == PrimitiveKind::Capsule);
  CHECK(parts[3].size.x() == 0.05);
  CHECK(parts[3].size.y() == doctest::Approx(0.2));
  CHECK(parts[4].kind == PrimitiveKind::Ellipsoid);
  CHECK(near(parts[4].size, Vec3(0.1, 0.2, 0.3)));
  CHECK(b.scale == 2);
  CHECK(near(b.rotate * Vec3::UnitY(), Vec3::UnitZ()));  // 90 degrees about x
  CHECK(near(b.translate, Vec3(0, 1, 0)));
  CHECK(b.cell_size == 0.1);
  CHECK(b.surface_resolution == 0.02);
  CHECK(b.material.model == "corotational");
  CHECK(b.material.E == 1.5e5);
  CHECK(b.material.nu == 0.25);
  CHECK(b.material.rho == 500);
  CHECK(b.damping_mass == 0.1);
  CHECK(b.damping_stiffness == 0.01);
  REQUIRE(b.fixed.size() == 2);
  CHECK(b.fixed[0].kind == RegionDesc::Kind::Box);
  CHECK(near(b.fixed[0].a, Vec3(-1, -1, -1)));
  CHECK(near(b.fixed[0].b, Vec3(-0.4, 1, 1)));
  CHECK(b.fixed[1].kind == RegionDesc::Kind::HalfSpace);
  CHECK(near(b.fixed[1].b, Vec3(0, 0, -1)));  // normalised
  CHECK(near(b.velocity, Vec3(1, 0, 0)));
  CHECK(b.energy_limit.enabled);
  CHECK(b.energy_limit.Umax == 0.5);
  CHECK(b.energy_limit.jacobian == "warped");
  REQUIRE(b.energy_limit.regions.size() == 1);
  CHECK(b.energy_limit.regions[0].Umax == 0.2);
  CHECK(near(b.energy_limit.regions[0].region.b, Vec3(1, 1, 1)));

  const sinew::BodyDesc& m = s.bodies[1];
  CHECK(m.json_path == "bodies[1]");
  CHECK(m.name == "body1");
  CHECK(m.shape.parts.empty());
  CHECK(m.mesh_path == (dir / "meshes" / "tet.obj").lexically_normal().string());
  CHECK(fs::path(m.mesh_path).is_absolute());
  CHECK(m.material.nu == 0);
  CHECK_FALSE(m.energy_limit.enabled);

  REQUIRE(s.obstacles.size() == 2);
  CHECK(s.obstacles[0].json_path == "obstacles[0]");
  CHECK(s.obstacles[0].type == "plane");
  CHECK(near(s.obstacles[0].point, Vec3(0, -1, 0)));
  CHECK(near(s.obstacles[0].normal, Vec3(0, 1, 0)));  // normalised
  CHECK(s.obstacles[0].friction == 0.8);
  CHECK(s.obstacles[1].json_path == "obstacles[1]");
  CHECK(s.obstacles[1].friction == 0.5);  // defaults
  fs::remove_all(dir);
}

TEST_CASE("scene parser: defaults of a minimal scene") {
  const SceneDesc s = sinew::parse_scene_text(minimal_scene().dump(), "dir/drop.json", "");
  CHECK(s.path.empty());
  CHECK(s.name == "drop");  // the file name's stem
  CHECK(near(s.gravity, Vec3(0, -9.81, 0)));
  CHECK(s.h == doctest::Approx(1.0 / 60));
  CHECK(s.fps == 60);
  CHECK(s.frames == 120);
  CHECK(s.solver.linear == "cholmod");
  CHECK(s.solver.stale_factor_precision == "single");
  CHECK(s.obstacles.empty());
  REQUIRE(s.bodies.size() == 1);
  const sinew::BodyDesc& b = s.bodies[0];
  CHECK(b.name == "body0");
  CHECK(b.scale == 1);
  CHECK(b.rotate.isIdentity());
  CHECK(b.surface_resolution == 0);
  CHECK(b.material.model == "corotational");
  CHECK(b.damping_mass == 0);
  CHECK(b.fixed.empty());
  CHECK_FALSE(b.energy_limit.enabled);
}

TEST_CASE("scene parser: the step guards' limits") {
  json scene = minimal_scene();
  CHECK(sinew::parse_scene_text(scene.dump(), "test.json", "").solver.divergence_violation_limit == 1000);
  scene["solver"]["divergence_violation_limit"] = 50;
  scene["solver"]["budget_violation_limit"] = 5;
  const SceneDesc s = sinew::parse_scene_text(scene.dump(), "test.json", "");
  CHECK(s.solver.divergence_violation_limit == 50);
  CHECK(s.solver.budget_violation_limit == 5);
  scene["solver"]["divergence_violation_limit"] = 0;
  check_error(scene, "solver.divergence_violation_limit: expected a number > 0, got 0");
}

TEST_CASE("scene parser: integral numbers written as floats are accepted for integers") {
  json scene = minimal_scene();
  scene["frames"] = 240.0;
  CHECK(parse(scene).frames == 240);
}

TEST_CASE("scene parser: steps per frame") {
  SceneDesc s;
  s.fps = 60;
  s.h = 1.0 / 60;
  CHECK(s.steps_per_frame() == 1);
  s.h = 1.0 / 240;
  CHECK(s.steps_per_frame() == 4);
  s.h = 0.004;  // 4.17 steps -> 4
  CHECK(s.steps_per_frame() == 4);
  s.h = 0.1;  // longer than a frame
  CHECK(s.steps_per_frame() == 1);
}

TEST_CASE("scene parser: Euler angles are applied as Rz * Ry * Rx") {
  json scene = minimal_scene();
  scene["bodies"][0]["transform"] = {{"rotation_deg", {90, 0, 90}}};
  const sinew::Mat3 r = parse(scene).bodies[0].rotate;
  // x: Rx leaves it, Rz turns it to y. y: Rx turns it to z, Rz leaves it.
  CHECK(near(r * Vec3::UnitX(), Vec3::UnitY()));
  CHECK(near(r * Vec3::UnitY(), Vec3::UnitZ()));
  CHECK(near(r * Vec3::UnitZ(), Vec3::UnitX()));
}

TEST_CASE("scene parser: RegionDesc::contains") {
  RegionDesc box;
  box.kind = RegionDesc::Kind::Box;
  box.a = Vec3(0, 0, 0);
  box.b = Vec3(1, 2, 3);
  CHECK(box.contains(Vec3(0.5, 1, 1)));
  CHECK(box.contains(Vec3(0, 2, 3)));  // boundary included
  CHECK_FALSE(box.contains(Vec3(0.5, 2.1, 1)));
  CHECK_FALSE(box.contains(Vec3(-0.1, 1, 1)));

  RegionDesc half;
  half.kind = RegionDesc::Kind::HalfSpace;
  half.a = Vec3(0, 1, 0);
  half.b = Vec3(0, 1, 0);
  CHECK(half.contains(Vec3(5, 0.5, -3)));
  CHECK(half.contains(Vec3(0, 1, 0)));
  CHECK_FALSE(half.contains(Vec3(0, 1.5, 0)));
}

TEST_CASE("scene parser: number errors name the path and the accepted range") {
  json scene = minimal_scene();
  scene["bodies"][0]["material"]["E"] = -5;
  CHECK(error_of(scene) == "test.json: bodies[0].material.E: expected a number > 0, got -5");

  scene = minimal_scene();
  scene["bodies"][0]["material"]["nu"] = 0.5;
  check_error(scene, "bodies[0].material.nu: expected a number in [0, 0.5), got 0.5");
  scene["bodies"][0]["material"]["nu"] = -0.1;
  check_error(scene, "bodies[0].material.nu: expected a number in [0, 0.5), got -0.1");

  scene = minimal_scene();
  scene["bodies"][0]["material"]["rho"] = "heavy";
  check_error(scene, "bodies[0].material.rho: expected a number > 0, got \"heavy\"");

  scene = minimal_scene();
  scene["bodies"][0]["cell_size"] = 0;
  check_error(scene, "bodies[0].cell_size: expected a number > 0, got 0");

  scene = minimal_scene();
  scene["bodies"][0]["surface_resolution"] = -0.01;
  check_error(scene, "bodies[0].surface_resolution: expected a number >= 0, got -0.01");

  scene = minimal_scene();
  scene["h"] = true;
  check_error(scene, "h: expected a number > 0, got true");
  scene["h"] = 0;
  check_error(scene, "h: expected a number > 0, got 0");

  scene = minimal_scene();
  scene["fps"] = -24;
  check_error(scene, "fps: expected a number > 0, got -24");

  scene = minimal_scene();
  scene["bodies"][0]["damping"] = {{"mass", -1}};
  check_error(scene, "bodies[0].damping.mass: expected a number >= 0, got -1");
  scene["bodies"][0]["damping"] = {{"stiffness", "x"}};
  check_error(scene, "bodies[0].damping.stiffness: expected a number >= 0, got \"x\"");

  scene = minimal_scene();
  scene["bodies"][0]["transform"] = {{"scale", 0}};
  check_error(scene, "bodies[0].transform.scale: expected a number > 0, got 0");
}

TEST_CASE("scene parser: integer errors") {
  json scene = minimal_scene();
  scene["frames"] = 1.5;
  check_error(scene, "frames: expected an integer > 0, got 1.5");
  scene["frames"] = 0;
  check_error(scene, "frames: expected an integer > 0, got 0");
  scene["frames"] = "10";
  check_error(scene, "frames: expected an integer > 0, got \"10\"");
  scene["frames"] = 1e12;
  check_error(scene, "frames: expected an integer > 0");

  scene = minimal_scene();
  scene["solver"] = {{"pcg_max_iterations", 0}};
  check_error(scene, "solver.pcg_max_iterations: expected an integer > 0, got 0");
}

TEST_CASE("scene parser: numbers must be finite") {
  const std::string message = error_of_text("{\"fps\": 60,\n \"h\": 1e999, \"bodies\": []}");
  CHECK(contains(message, "test.json:2:7: invalid JSON: "));
  CHECK(contains(message, "1e999"));
}

TEST_CASE("scene parser: vector errors") {
  json scene = minimal_scene();
  scene["gravity"] = {0, -9.81};
  check_error(scene, "gravity: expected an array of 3 numbers, got [0,-9.81]");
  scene["gravity"] = {0, "down", 0};
  check_error(scene, "gravity: expected an array of 3 numbers, got [0,\"down\",0]");
  scene["gravity"] = 9.81;
  check_error(scene, "gravity: expected an array of 3 numbers, got 9.81");

  scene = minimal_scene();
  scene["bodies"][0]["velocity"] = {1, 2, 3, 4};
  check_error(scene, "bodies[0].velocity: expected an array of 3 numbers, got [1,2,3,4]");

  scene = minimal_scene();
  scene["bodies"][0]["shape"][0]["half_extents"] = {1, 0, 1};
  check_error(scene, "bodies[0].shape[0].half_extents: expected an array of 3 numbers > 0");
}

TEST_CASE("scene parser: string and choice errors") {
  json scene = minimal_scene();
  scene["name"] = 3;
  check_error(scene, "name: expected a string, got 3");

  scene = minimal_scene();
  scene["bodies"][0]["material"]["model"] = "neohookian";
  check_error(scene,
              "bodies[0].material.model: expected one of \"corotational\", \"stable_neo_hookean\", "
              "\"neo_hookean\", \"corotational_hyperelastic\", \"arap\", \"stvk\", \"fung\", "
              "\"arruda_boyce\", got \"neohookian\"");

  scene = minimal_scene();
  scene["solver"] = {{"linear", "lu"}};
  check_error(scene, "solver.linear: expected one of \"cholmod\", \"pcg\", got \"lu\"");

  scene = minimal_scene();
  scene["solver"] = {{"sqp_acceleration", "anderson"}};
  check_error(scene, "solver.sqp_acceleration: expected one of \"conjugate\", \"none\", got \"anderson\"");
  CHECK(sinew::parse_scene_text(minimal_scene().dump(), "test.json", "").solver.sqp_restoration == "none");
  scene["solver"] = {{"sqp_restoration", "accept"}};
  CHECK(sinew::parse_scene_text(scene.dump(), "test.json", "").solver.sqp_restoration == "accept");
  scene["solver"] = {{"sqp_restoration", "always"}};
  check_error(scene, "solver.sqp_restoration: expected one of \"accept\", \"none\", got \"always\"");
  CHECK(sinew::parse_scene_text(minimal_scene().dump(), "test.json", "").solver.sqp_kkt_stop == "on");
  scene["solver"] = {{"sqp_kkt_stop", "off"}};
  CHECK(sinew::parse_scene_text(scene.dump(), "test.json", "").solver.sqp_kkt_stop == "off");
  scene["solver"] = {{"sqp_kkt_stop", true}};
  check_error(scene, "solver.sqp_kkt_stop: expected one of \"on\", \"off\", got true");
  scene["solver"] = {{"stale_factor_precision", "double"}};
  CHECK(sinew::parse_scene_text(scene.dump(), "test.json", "").solver.stale_factor_precision == "double");
  scene["solver"] = {{"stale_factor_precision", "half"}};
  check_error(scene, "solver.stale_factor_precision: expected one of \"single\", \"double\", got \"half\"");
  CHECK(sinew::parse_scene_text(minimal_scene().dump(), "test.json", "").solver.hessian_reuse_tolerance == 1e-3);
  scene["solver"] = {{"hessian_reuse_tolerance", 0}};
  CHECK(sinew::parse_scene_text(scene.dump(), "test.json", "").solver.hessian_reuse_tolerance == 0);
  scene["solver"] = {{"hessian_reuse_tolerance", -1e-3}};
  check_error(scene, "solver.hessian_reuse_tolerance: expected a number >= 0, got -0.001");

  scene = minimal_scene();
  scene["bodies"][0]["shape"][0]["type"] = "cube";
  check_error(scene, "bodies[0].shape[0].type: expected one of \"box\", \"sphere\", \"cylinder\", "
                     "\"capsule\", \"ellipsoid\", got \"cube\"");

  scene = minimal_scene();
  scene["bodies"][0]["energy_limit"] = {{"Umax", 1}, {"jacobian", "approx"}};
  check_error(scene, "bodies[0].energy_limit.jacobian: expected one of \"exact\", \"warped\"");

  scene = minimal_scene();
  scene["obstacles"] = {{{"type", "cone"}}};
  check_error(scene, "obstacles[0].type: expected one of \"plane\", \"box\", \"sphere\", \"capsule\", \"mesh\", got \"cone\"");
}

TEST_CASE("scene parser: missing required keys") {
  json scene = minimal_scene();
  scene["bodies"][0].erase("cell_size");
  check_error(scene, "bodies[0]: missing required key 'cell_size'");

  scene = minimal_scene();
  scene["bodies"][0].erase("material");
  check_error(scene, "bodies[0]: missing required key 'material'");

  scene = minimal_scene();
  scene["bodies"][0]["material"].erase("nu");
  check_error(scene, "bodies[0].material: missing required key 'nu'");

  scene = minimal_scene();
  scene.erase("bodies");
  check_error(scene, "(root): missing required key 'bodies'");

  scene = minimal_scene();
  scene["bodies"][0]["shape"][0].erase("type");
  check_error(scene, "bodies[0].shape[0]: missing required key 'type'");

  scene = minimal_scene();
  scene["bodies"][0]["shape"][0] = {{"type", "sphere"}};
  check_error(scene, "bodies[0].shape[0]: missing required key 'radius'");

  scene = minimal_scene();
  scene["bodies"][0]["energy_limit"] = json::object();
  check_error(scene, "bodies[0].energy_limit: missing required key 'Umax'");
}

TEST_CASE("scene parser: unknown keys at every level, with the closest key suggested") {
  json scene = minimal_scene();
  scene["bodies"][0]["celsize"] = 0.1;
  check_error(scene, "bodies[0].celsize: unknown key 'celsize' (did you mean 'cell_size'?)");

  scene = minimal_scene();
  scene["gravty"] = {0, 0, 0};
  check_error(scene, "gravty: unknown key 'gravty' (did you mean 'gravity'?)");

  scene = minimal_scene();
  scene["bodies"][0]["material"]["e"] = 5;
  check_error(scene, "bodies[0].material.e: unknown key 'e' (did you mean 'E'?)");

  scene = minimal_scene();
  scene["solver"] = {{"pcg_tolerence", 1e-6}};
  check_error(scene,
              "solver.pcg_tolerence: unknown key 'pcg_tolerence' (did you mean 'pcg_tolerance'?)");

  scene = minimal_scene();
  scene["obstacles"] = {{{"frcition", 0.2}}};
  check_error(scene, "obstacles[0].frcition: unknown key 'frcition' (did you mean 'friction'?)");

  scene = minimal_scene();
  scene["bodies"][0]["fixed"] = {{{"box", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}, {"mid", 1}}}}};
  check_error(scene, "bodies[0].fixed[0].box.mid: unknown key 'mid' (did you mean 'min'?)");

  // A key valid for another primitive type is unknown here.
  scene = minimal_scene();
  scene["bodies"][0]["shape"][0]["radius"] = 0.1;
  check_error(scene, "bodies[0].shape[0].radius: unknown key 'radius'");

  // Nothing close: no suggestion, the known keys are listed instead.
  scene = minimal_scene();
  scene["wibble"] = 1;
  const std::string message = error_of(scene);
  CHECK(contains(message, "test.json: wibble: unknown key 'wibble' (expected one of: 'name',"));
  CHECK_FALSE(contains(message, "did you mean"));
}

TEST_CASE("scene parser: structure errors") {
  check_error(json::array({1, 2}), "(root): expected an object, got [1,2]");

  json scene = minimal_scene();
  scene["bodies"] = json::array();
  check_error(scene, "bodies: expected a non-empty array, got []");
  scene["bodies"] = json::object();
  check_error(scene, "bodies: expected a non-empty array, got {}");

  scene = minimal_scene();
  scene["bodies"][0]["material"] = 5;
  check_error(scene, "bodies[0].material: expected an object, got 5");

  scene = minimal_scene();
  scene["bodies"][0]["shape"] = json::array();
  check_error(scene, "bodies[0].shape: expected a non-empty array, got []");

  scene = minimal_scene();
  scene["bodies"].push_back(scene["bodies"][0]);
  scene["bodies"][0]["name"] = "a";
  scene["bodies"][1]["name"] = "a";
  check_error(scene, "bodies[1]: duplicate body name 'a' (also used by bodies[0])");
}

TEST_CASE("scene parser: shape and mesh are exclusive") {
  json scene = minimal_scene();
  scene["bodies"][0].erase("shape");
  check_error(scene, "bodies[0]: expected exactly one of 'shape', 'mesh' or 'tet_mesh', got none");

  scene = minimal_scene();
  scene["bodies"][0]["mesh"] = "x.obj";
  check_error(scene, "bodies[0]: expected exactly one of 'shape', 'mesh' or 'tet_mesh', got 'shape', 'mesh'");
}

TEST_CASE("scene parser: primitive sizes") {
  json scene = minimal_scene();
  scene["bodies"][0]["shape"][0] = {{"type", "sphere"}, {"radius", -1}};
  check_error(scene, "bodies[0].shape[0].radius: expected a number > 0, got -1");

  scene["bodies"][0]["shape"][0] = {{"type", "cylinder"}, {"radius", 0.1}, {"length", 0}};
  check_error(scene, "bodies[0].shape[0].length: expected a number > 0, got 0");

  // A capsule of zero length is a sphere.
  scene["bodies"][0]["shape"][0] = {{"type", "capsule"}, {"radius", 0.1}, {"length", 0}};
  CHECK(parse(scene).bodies[0].shape.parts[0].size.y() == 0);

  scene["bodies"][0]["shape"][0] = {{"type", "ellipsoid"}, {"semi_axes", {1, -1, 1}}};
  check_error(scene, "bodies[0].shape[0].semi_axes: expected an array of 3 numbers > 0");
}

TEST_CASE("scene parser: region errors") {
  json scene = minimal_scene();
  scene["bodies"][0]["fixed"] = {{{"box", {{"min", {0, 0, 0}}, {"max", {1, 0, 1}}}}}};
  check_error(scene, "bodies[0].fixed[0].box: expected min < max in every component, "
                     "got min [0,0,0], max [1,0,1]");

  scene["bodies"][0]["fixed"] = {{{"box", {{"min", {0, 0, 0}}}}}};
  check_error(scene, "bodies[0].fixed[0].box: missing required key 'max'");

  scene["bodies"][0]["fixed"] = {{{"half_space", {{"point", {0, 0, 0}}, {"normal", {0, 0, 0}}}}}};
  check_error(scene,
              "bodies[0].fixed[0].half_space.normal: expected a non-zero array of 3 numbers");

  scene["bodies"][0]["fixed"] = json::array({json::object()});  // {json::object()} is the object itself for clang, an array of it for gcc
  check_error(scene,
              "bodies[0].fixed[0]: expected exactly one of 'box' or 'half_space', got neither");

  const json box = {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}};
  const json half = {{"point", {0, 0, 0}}, {"normal", {0, 1, 0}}};
  scene["bodies"][0]["fixed"] = {{{"box", box}, {"half_space", half}}};
  check_error(scene, "bodies[0].fixed[0]: expected exactly one of 'box' or 'half_space', got both");

  scene["bodies"][0]["fixed"] = {{{"box", box}}};
  scene["bodies"][0]["energy_limit"] = {{"Umax", 1}, {"regions", {{{"box", box}, {"Umax", -2}}}}};
  check_error(scene, "bodies[0].energy_limit.regions[0].Umax: expected a number > 0, got -2");
  scene["bodies"][0]["energy_limit"] = {{"Umax", 0}};
  check_error(scene, "bodies[0].energy_limit.Umax: expected a number > 0, got 0");
}

TEST_CASE("scene parser: obstacle and solver errors") {
  json scene = minimal_scene();
  scene["obstacles"] = {{{"normal", {0, 0, 0}}}};
  check_error(scene, "obstacles[0].normal: expected a non-zero array of 3 numbers, got [0,0,0]");
  scene["obstacles"] = {{{"friction", -0.1}}};
  check_error(scene, "obstacles[0].friction: expected a number >= 0, got -0.1");
  scene["obstacles"] = json::object();
  check_error(scene, "obstacles: expected an array, got {}");

  scene = minimal_scene();
  scene["solver"] = {{"activation_margin", 1}};
  check_error(scene, "solver.activation_margin: expected a number in [0, 1), got 1");
  scene["solver"] = {{"sqp_tolerance", 0}};
  check_error(scene, "solver.sqp_tolerance: expected a number > 0, got 0");
}

TEST_CASE("scene parser: JSON syntax errors report line and column") {
  std::string message = error_of_text("{\n  \"h\": 0.01,\n  \"fps\": x\n}");
  CHECK(contains(message, "test.json:3:10: invalid JSON: "));
  CHECK_FALSE(contains(message, "json.exception"));

  message = error_of_text("{\"h\": 1,");  // unexpected end of input, just past the end
  CHECK(contains(message, "test.json:1:9: invalid JSON: "));

  // Columns count characters, not bytes: \xc3\xa9 is one character.
  message = error_of_text("{\"\xc3\xa9\": x}");
  CHECK(contains(message, "test.json:1:7: invalid JSON: "));
}

TEST_CASE("scene parser: duplicate keys are errors") {
  const std::string text = R"({"bodies": [ {"shape": [{"type": "box", "half_extents": [1, 1, 1]}],
    "cell_size": 0.1, "material": {"E": 1, "nu": 0.3, "rho": 1, "E": 2}} ]})";
  CHECK(error_of_text(text) == "test.json: bodies[0].material.E: duplicate key 'E'");
}

TEST_CASE("scene parser: mesh paths") {
  const fs::path dir = scene_test_dir("mesh");
  write_file(dir / "assets" / "tet.obj", kTetraObj);
  fs::create_directories(dir / "adir.obj");

  json scene = minimal_scene();
  scene["bodies"][0].erase("shape");
  scene["bodies"][0]["mesh"] = "assets/tet.obj";
  CHECK(parse(scene, dir.string()).bodies[0].mesh_path == (dir / "assets" / "tet.obj").string());

  // Absolute paths ignore the base directory.
  scene["bodies"][0]["mesh"] = (dir / "assets" / "tet.obj").string();
  CHECK(parse(scene, "/nonexistent").bodies[0].mesh_path == (dir / "assets" / "tet.obj").string());

  scene["bodies"][0]["mesh"] = "assets/../missing.obj";
  std::string message = error_of(scene, dir.string());
  CHECK(message == "test.json: bodies[0].mesh: mesh file 'assets/../missing.obj' not found "
                   "(resolved to '" + (dir / "missing.obj").string() + "')");

  scene["bodies"][0]["mesh"] = "adir.obj";
  message = error_of(scene, dir.string());
  CHECK(contains(message, "test.json: bodies[0].mesh: mesh file 'adir.obj' is not a regular file"));

  scene["bodies"][0]["mesh"] = "assets/tet.obj";
  scene["bodies"][0]["surface_resolution"] = 0.01;
  message = error_of(scene, dir.string());
  CHECK(contains(message, "test.json: bodies[0].surface_resolution: only allowed with 'shape'"));
  fs::remove_all(dir);
}

TEST_CASE("scene parser: load_scene errors name the file") {
  const fs::path dir = scene_test_dir("load");
  const std::string missing = (dir / "nope.json").string();
  try {
    sinew::load_scene(missing);
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()) == missing + ": cannot open");
  }

  const std::string bad = (dir / "bad.json").string();
  json scene = minimal_scene();
  scene["bodies"][0]["material"]["nu"] = 0.7;
  write_file(bad, scene.dump(2));
  try {
    sinew::load_scene(bad);
    FAIL("expected an InputError");
  } catch (const InputError& e) {
    CHECK(contains(e.what(), bad + ": bodies[0].material.nu: expected a number in [0, 0.5)"));
  }
  fs::remove_all(dir);
}

// Found by tools/fuzz (fuzz_scene_parser): a 400 KB file of nested brackets took over 2 GB
// (every open level kept its JSON path, so memory grew with the square of the depth).
TEST_CASE("scene parser: deeply nested JSON is an error") {
  const int depth = 100000;
  const std::string deep = std::string(depth, '[') + std::string(depth, ']');
  CHECK(error_of_text(R"({"bodies": )" + deep + "}") ==
        "test.json: invalid JSON: arrays and objects nested more than 64 levels deep");
  CHECK(error_of_text(R"({"name": )" + deep + R"(, "bodies": []})") ==
        "test.json: invalid JSON: arrays and objects nested more than 64 levels deep");
  // 64 levels still parse (and fail on the schema instead).
  const std::string ok = std::string(63, '[') + std::string(63, ']');
  CHECK(contains(error_of_text(R"({"name": )" + ok + R"(, "bodies": []})"), "name: expected a string"));
}

TEST_CASE("scene parser: material volume_term") {
  json scene = minimal_scene();
  CHECK_FALSE(parse(scene).bodies[0].material.mean_dilatation);  // default per point
  scene["bodies"][0]["material"]["model"] = "stable_neo_hookean";
  scene["bodies"][0]["material"]["volume_term"] = "mean_dilatation";
  CHECK(parse(scene).bodies[0].material.mean_dilatation);

  scene["bodies"][0]["material"]["volume_term"] = "mean";
  check_error(scene, "bodies[0].material.volume_term: expected one of \"per_point\", \"mean_dilatation\", got \"mean\"");

  scene["bodies"][0]["material"]["volume_term"] = "mean_dilatation";
  scene["bodies"][0]["material"]["model"] = "stvk";
  check_error(scene, "bodies[0].material.volume_term: \"mean_dilatation\" needs a model of the form f(Ic) + g(J)");
  scene["bodies"][0]["material"]["model"] = "corotational";
  check_error(scene, "bodies[0].material.volume_term: \"mean_dilatation\" needs a model of the form f(Ic) + g(J)");

  scene["bodies"][0]["material"]["model"] = "neo_hookean";
  scene["bodies"][0]["elements"] = "tet";
  check_error(scene, "bodies[0].material.volume_term: \"mean_dilatation\" is for hex elements");
}
