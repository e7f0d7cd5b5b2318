#include "tools/hyperelastic_drop.hpp"

#include <filesystem>

namespace sinew::bench {

// bunny_5 is ~176 units tall along z: scaled to ~0.35 m, z turned to y. cube_20 spans
// [0.25, 3] x [0, 0.75] x [0, 0.75]: scaled by 0.2 to a 0.55 x 0.15 x 0.15 m bar.
const std::vector<MeshCase> kMeshes = {
    {"bunny_5", R"({"scale": 0.002, "rotation_deg": [-90, 0, 0], "translate": [0, 0.05, 0]})"},
    {"cube_20", R"({"scale": 0.2, "translate": [-0.3, 0.05, -0.075]})"}};

std::vector<std::string> mesh_names() {
  std::vector<std::string> names;
  for (const MeshCase& m : kMeshes) names.push_back(m.name);
  return names;
}

std::string mesh_base(const MeshCase& mesh) {
  return std::string(SINEW_SOURCE_DIR) + "/../shared/meshes/tet/" + mesh.name;
}

bool mesh_present(const MeshCase& mesh) {
  const std::string base = mesh_base(mesh);
  return std::filesystem::exists(base + ".node") && std::filesystem::exists(base + ".ele");
}

SceneDesc drop_scene(const std::string& mesh_path, const MeshCase& mesh, int newton_iterations, double tolerance,
                     int delassus_reuse, int refactor_interval) {
  const std::string text = R"({"name": ")" + mesh.name + R"(", "h": 0.0166666666666667,
    "solver": {"newton_max_iterations": )" + std::to_string(newton_iterations) +
                           R"(, "newton_tolerance": )" + std::to_string(tolerance) +
                           R"(, "delassus_reuse": )" + std::to_string(delassus_reuse) +
                           R"(, "refactor_interval": )" + std::to_string(refactor_interval) + R"(, "sleep_steps": 0},
    "bodies": [{"name": ")" + mesh.name + R"(", "tet_mesh": ")" + mesh_path + R"(", "transform": )" +
                           mesh.transform + R"(,
      "material": {"model": "stable_neo_hookean", "E": 5e5, "nu": 0.45, "rho": 1000},
      "damping": {"mass": 1}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5}]})";
  return parse_scene_text(text, mesh.name, ".");
}

}  // namespace sinew::bench
