// sinew_volume_preservation: paper 003's volume comparison (sec. 7, the elbow). Runs a
// bending scene (default assets/scenes/paper003_elbow_snh.json: a bar fixed at one end, its
// other end rotated 90 degrees by driven nodes, then held) for several materials and
// Poisson ratios, and prints a Markdown table of the bent, settled state: the worst
// |J_e - 1| over elements and the total volume change sum_e J_e V_e / sum_e V_e - 1, with
// J_e each element's deformed over rest volume: det F of a tet; for a hex the mean of det F
// at its 8 Gauss points, which integrate the trilinear map's det F exactly. A material whose
// run fails (NaN or a singular system) is reported as such. After the scene's own elements, the models of the
// form f(Ic) + g(J) run again on the unsplit hex lattice, with g at each Gauss point and at
// the element's mean dilatation (material "volume_term"), to show what locking does.
#include <Eigen/LU>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/hyperelastic_element.hpp"
#include "engine/core/error.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

struct VolumeResult {
  bool ok = true;
  double worst = 0;   // max_e |J_e - 1|
  double total = 0;   // sum J V / sum V - 1
  double seconds = 0;
  long newton = 0;
};

// How the bodies are discretised: as the scene says, or as hexes with the volume term per
// Gauss point or at the mean dilatation.
enum class Elements { AsScene, HexPerPoint, HexMeanDilatation };

const char* elements_name(Elements elements, const SceneDesc& scene) {
  switch (elements) {
    case Elements::HexPerPoint: return "hex, g(J) per point";
    case Elements::HexMeanDilatation: return "hex, g(mean J)";
    case Elements::AsScene: break;
  }
  return scene.bodies.empty() ? "" : scene.bodies.front().elements.c_str();
}

VolumeResult run(SceneDesc scene, const std::string& material, double nu, Elements elements) {
  for (BodyDesc& b : scene.bodies) {
    b.material.model = material;
    b.material.nu = nu;
    if (elements != Elements::AsScene) {
      b.elements = "hex";
      b.material.mean_dilatation = elements == Elements::HexMeanDilatation;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  VolumeResult r;
  const int steps = scene.frames * scene.steps_per_frame();
  for (int s = 0; s < steps && r.ok; ++s) {
    r.ok = world.step();
    if (world.profile().iterations.count("newton")) r.newton += world.profile().iterations.at("newton");
  }
  const Model& model = world.model();
  double volume = 0, deformed = 0;
  for (int e = 0; e < model.num_elements; ++e) {
    const ElementNodes nodes = gather_element_nodes(model, world.state().x, e);
    const ElementQuadrature quad = element_quadrature(model, e);
    double J = 0;
    for (int q = 0; q < quad.points; ++q) J += deformation_gradient(quad.dN_dX[q], nodes).determinant() / quad.points;
    const double V = element_rest_volume(model, e);
    r.worst = std::max(r.worst, std::abs(J - 1));
    volume += V;
    deformed += J * V;
  }
  r.total = deformed / volume - 1;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper003_elbow_snh.json";
  try {
    const SceneDesc scene = load_scene(path);
    // Every hyperelastic material sinew has (ARAP has no volume term: nu changes nothing).
    const std::vector<std::string> materials = {"stable_neo_hookean", "neo_hookean", "corotational_hyperelastic",
                                                "stvk", "arap", "fung", "arruda_boyce"};
    const std::vector<double> nus = {0.3, 0.45, 0.49, 0.495};
    std::printf("| material | elements | nu | worst abs(J - 1) | total volume change | Newton iterations | run s |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    const auto row = [&](const std::string& material, Elements elements) {
      for (double nu : nus) {
        const VolumeResult r = run(scene, material, nu, elements);
        const char* name = elements_name(elements, scene);
        if (!r.ok) {
          std::printf("| %s | %s | %g | failed (non-finite or singular) | | %ld | %.1f |\n", material.c_str(), name, nu,
                      r.newton, r.seconds);
        } else {
          std::printf("| %s | %s | %g | %.3e | %+.3e | %ld | %.1f |\n", material.c_str(), name, nu, r.worst, r.total,
                      r.newton, r.seconds);
        }
        std::fflush(stdout);
      }
    };
    for (const std::string& material : materials) row(material, Elements::AsScene);
    // The models mean dilatation applies to (docs/scenes.md, "volume_term").
    for (const char* material : {"stable_neo_hookean", "neo_hookean"})
      for (Elements elements : {Elements::HexPerPoint, Elements::HexMeanDilatation}) row(material, elements);
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
