#pragma once
// Shared by the Newton step tests: a Stable Neo-Hookean box of tets (0.3 x 0.2 x 0.2 m, E 200
// kPa, nu 0.45) tilted 8 degrees and dropped 5 cm onto a plane (friction 0.5), h = 1/60 s;
// and a step's iteration counts by name.
#include <string>

#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

namespace sinew::test {

// solver_fields: the "solver" object's members, e.g. "\"newton_max_iterations\": 1".
inline World snh_landing_box(const std::string& solver_fields) {
  const std::string text = R"({"h": 0.0166666666666667, "solver": {)" + solver_fields + R"(},
    "bodies": [{"name": "box", "shape": [{"type": "box", "half_extents": [0.15, 0.1, 0.1]}],
      "transform": {"translate": [0, 0.15, 0], "rotation_deg": [0, 0, 8]}, "cell_size": 0.05,
      "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 200000.0, "nu": 0.45, "rho": 1000},
      "damping": {"mass": 1}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5}]})";
  return World(build_model(parse_scene_text(text, "snh_landing_box", "."), [](const std::string&) {}));
}

// profile.iterations[name], 0 when the step did not report it.
inline int iteration_count(const StepProfile& profile, const char* name) {
  const auto it = profile.iterations.find(name);
  return it == profile.iterations.end() ? 0 : it->second;
}

}  // namespace sinew::test
