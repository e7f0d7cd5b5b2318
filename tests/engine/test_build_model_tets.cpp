// Tet bodies in build_model: a lattice split into tets and a TetGen mesh file.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "engine/collision/surface_cells.hpp"
#include "engine/core/error.hpp"
#include "engine/geometry/embedding.hpp"
#include "engine/world.hpp"
#include "tests/engine/assembly/element_schedule_check.hpp"

using namespace sinew;
namespace fs = std::filesystem;

namespace {

void check_colours_share_no_node(const Model& m) {
  int total = 0;
  for (const auto& colour : m.element_colors) {
    std::vector<int> seen(m.num_nodes, 0);
    for (int e : colour)
      for (int n : m.element_nodes[e])
        if (n >= 0) CHECK(seen[n]++ == 0);
    total += static_cast<int>(colour.size());
  }
  CHECK(total == m.num_elements);
  check_element_schedule(m);
}

}  // namespace

TEST_CASE("build_model: a lattice split into tets keeps mass, volume and the embedded surface") {
  const SceneDesc scene = parse_scene_text(R"({"bodies": [
    {"name": "a", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
     "elements": "tet", "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})", "tets", ".");
  const Model m = build_model(scene, [](const std::string&) {});
  REQUIRE(m.bodies.size() == 1);
  const Body& b = m.bodies[0];
  CHECK(b.element_type == ElementType::Tet4);
  CHECK(b.num_elements() == 6 * 4 * 2 * 2);
  double mass = 0, volume = 0;
  for (int n = 0; n < m.num_nodes; ++n) mass += m.node_mass[n];
  for (const Tet4Reference& r : m.tet_references) volume += r.volume;
  CHECK(volume == doctest::Approx(0.4 * 0.2 * 0.2).epsilon(1e-12));
  CHECK(mass == doctest::Approx(1000 * 0.4 * 0.2 * 0.2).epsilon(1e-12));
  for (const auto& nodes : m.element_nodes) CHECK(nodes[4] == -1);
  check_colours_share_no_node(m);
  // Barycentric embedding reproduces every rest surface vertex.
  std::vector<Vec3> embedded;
  compute_embedded_positions(b.embedding, b.lattice, m.rest_x, b.node_offset, embedded);
  double worst = 0;
  for (size_t i = 0; i < embedded.size(); ++i) worst = std::max(worst, (embedded[i] - b.rest_surface.vertices[i]).norm());
  CHECK(worst < 1e-12);
}

TEST_CASE("build_model: a TetGen body falls onto a plane and rests on it") {
  const fs::path dir = fs::temp_directory_path() / ("sinew_tets_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // A unit cube as 5 tets (corner tets + the central one).
  std::ofstream(dir / "cube.node") << "8 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 1 1 0\n4 0 0 1\n5 1 0 1\n6 0 1 1\n7 1 1 1\n";
  std::ofstream(dir / "cube.ele") << "5 4 0\n0 0 1 2 4\n1 1 3 2 7\n2 1 4 5 7\n3 2 6 4 7\n4 1 2 4 7\n";
  const std::string text = R"({"h": 0.01, "bodies": [{"name": "cube", "tet_mesh": "cube",
      "transform": {"scale": 0.2, "translate": [0, 0.05, 0]},
      "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.4, "rho": 500}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})";
  const Model model = build_model(parse_scene_text(text, "cube.json", dir.string()), [](const std::string&) {});
  CHECK(model.num_elements == 5);
  CHECK(model.has_hyperelastic);
  CHECK(model.bodies[0].rest_surface.triangles.size() == 12);  // two per cube face
  check_colours_share_no_node(model);
  World world(model);
  for (int i = 0; i < 100; ++i) REQUIRE(world.step());
  double lowest = 1e300;
  for (int n = 0; n < model.num_nodes; ++n) lowest = std::min(lowest, world.state().x[3 * n + 1]);
  // Fell 5 cm and stopped at the plane (contact tolerance 1e-4 m).
  CHECK(lowest > -1e-4);
  CHECK(lowest < 1e-3);
  fs::remove_all(dir);
}
