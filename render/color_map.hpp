#pragma once
// Per-element colour maps (Ue/Umax, volume ratio J), their scales, and their transfer to the
// embedded surface.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "engine/model.hpp"

namespace sinew {

enum class ColorMapKind { None, Energy, Volume };

// "none", "energy" or "volume"; throws std::invalid_argument naming the choices.
ColorMapKind parse_color_map(const std::string& name);
// The compute_element_fields() entry a map shows ("energy_ratio", "volume_ratio").
const char* color_map_field(ColorMapKind kind);

struct ColorScale {
  double lo = 0, hi = 1;
  std::string title;  // legend heading
};

// Energy: Ue/Umax on a fixed [0, 1] (1 = at the limit; above it saturates), so colours mean
// the same in every frame. Volume: symmetric around J = 1, widened to the largest |J - 1|
// seen so far (at least 0.005) and never narrowed, so a video does not flicker.
ColorScale update_scale(ColorMapKind kind, const std::vector<double>& values, const ColorScale* previous);

// Colour of `value` on `scale` (clamped to its ends). Energy: dark blue -> teal -> yellow ->
// red; volume: blue (compressed) -> white (J = 1) -> red (stretched).
Eigen::Vector3f map_color(ColorMapKind kind, const ColorScale& scale, double value);

// Per surface vertex of `body`, the value of the element the vertex is embedded in.
// `element_values` is indexed by global element (model.num_elements long).
void element_values_to_surface(const Body& body, const std::vector<double>& element_values,
                               std::vector<double>& vertex_values);

}  // namespace sinew
