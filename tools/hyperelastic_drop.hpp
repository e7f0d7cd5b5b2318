#pragma once
// The Stable Neo-Hookean drop of paper 003's meshes (issue 6) that sinew_bench_hyperelastic
// times step by step and sinew_bench_assembly takes its deformed state from: a TetGen mesh of
// ../shared/meshes/tet/ on a ground plane, h = 1/60 s, E = 5e5 Pa, nu = 0.45, rho = 1000
// kg/m^3, mass damping 1/s, friction 0.5. The body never sleeps (sleep_steps 0): each timed
// step is a step of the solver (until session 44 cube_20 slept from step 42, and 24 of the
// 60 timed steps cost nothing, which pulled its median down).
#include <string>
#include <vector>

#include "engine/scene/scene.hpp"

namespace sinew::bench {

struct MeshCase {
  std::string name;
  std::string transform;  // JSON "transform" placing the mesh just above the ground (y = 0)
};

// bunny_5 (5,266 tets) and cube_20 (13,200 tets).
extern const std::vector<MeshCase> kMeshes;
// Their names, for an option that picks one.
std::vector<std::string> mesh_names();

// The mesh's files without extension (SINEW_SOURCE_DIR/../shared/meshes/tet/NAME), and
// whether its .node and .ele are there.
std::string mesh_base(const MeshCase& mesh);
bool mesh_present(const MeshCase& mesh);

SceneDesc drop_scene(const std::string& mesh_path, const MeshCase& mesh, int newton_iterations, double tolerance,
                     int delassus_reuse, int refactor_interval);

}  // namespace sinew::bench
