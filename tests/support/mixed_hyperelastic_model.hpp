#pragma once
// Shared by the hyperelastic pass tests: a model whose elements cover every path of the pass.
#include <string>

#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

namespace sinew::test {

// Four bodies whose elements interleave in the blocks' groups of four: Stable Neo-Hookean tets
// and neo-Hookean tets (one-point invariant tets: batched SVDs, kept Hessians), neo-Hookean
// hexes (8 points: neither) and linear corotational hexes (not hyperelastic: not visited).
inline Model mixed_hyperelastic_model() {
  const char* text = R"({"h": 0.01, "gravity": [0, 0, 0], "bodies": [
    {"name": "snh_tets", "shape": [{"type": "box", "half_extents": [0.1, 0.05, 0.05]}], "cell_size": 0.05,
     "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 1000}},
    {"name": "nh_hexes", "shape": [{"type": "box", "half_extents": [0.1, 0.05, 0.05], "center": [0, 0.3, 0]}],
     "cell_size": 0.05, "elements": "hex", "material": {"model": "neo_hookean", "E": 1e5, "nu": 0.3, "rho": 1000}},
    {"name": "corotational", "shape": [{"type": "box", "half_extents": [0.1, 0.05, 0.05], "center": [0, 0.6, 0]}],
     "cell_size": 0.05, "elements": "hex", "material": {"model": "corotational", "E": 1e5, "nu": 0.3, "rho": 1000}},
    {"name": "nh_tets", "shape": [{"type": "box", "half_extents": [0.05, 0.05, 0.05], "center": [0, 0.9, 0]}],
     "cell_size": 0.05, "elements": "tet", "material": {"model": "neo_hookean", "E": 1e5, "nu": 0.3, "rho": 1000}}]})";
  return build_model(parse_scene_text(text, "mixed", "."), [](const std::string&) {});
}

}  // namespace sinew::test
