#include "render/color_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace sinew {
namespace {

struct Stop {
  float t;
  Eigen::Vector3f rgb;
};

Eigen::Vector3f interpolate(const std::vector<Stop>& stops, float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  for (size_t i = 1; i < stops.size(); ++i)
    if (t <= stops[i].t) {
      const float s = (t - stops[i - 1].t) / (stops[i].t - stops[i - 1].t);
      return (1 - s) * stops[i - 1].rgb + s * stops[i].rgb;
    }
  return stops.back().rgb;
}

}  // namespace

ColorMapKind parse_color_map(const std::string& name) {
  if (name == "none") return ColorMapKind::None;
  if (name == "energy") return ColorMapKind::Energy;
  if (name == "volume") return ColorMapKind::Volume;
  throw std::invalid_argument("unknown colour map '" + name + "' (expected energy, volume or none)");
}

const char* color_map_field(ColorMapKind kind) {
  return kind == ColorMapKind::Volume ? "volume_ratio" : "energy_ratio";
}

ColorScale update_scale(ColorMapKind kind, const std::vector<double>& values, const ColorScale* previous) {
  if (kind != ColorMapKind::Volume) return {0, 1, "Ue/Umax"};
  double half = previous ? previous->hi - 1 : 0.005;
  for (double j : values)
    if (std::isfinite(j)) half = std::max(half, std::abs(j - 1));
  return {1 - half, 1 + half, "J (volume)"};
}

Eigen::Vector3f map_color(ColorMapKind kind, const ColorScale& scale, double value) {
  static const std::vector<Stop> energy = {{0.0f, {0.16f, 0.20f, 0.50f}},
                                           {0.35f, {0.10f, 0.55f, 0.62f}},
                                           {0.70f, {0.95f, 0.82f, 0.25f}},
                                           {1.0f, {0.82f, 0.12f, 0.10f}}};
  static const std::vector<Stop> diverging = {{0.0f, {0.15f, 0.30f, 0.75f}},
                                              {0.5f, {0.94f, 0.94f, 0.94f}},
                                              {1.0f, {0.78f, 0.15f, 0.12f}}};
  const double span = scale.hi - scale.lo;
  const float t = span > 0 ? float((value - scale.lo) / span) : 0.5f;
  return interpolate(kind == ColorMapKind::Volume ? diverging : energy, std::isfinite(t) ? t : 0.0f);
}

void element_values_to_surface(const Body& body, const std::vector<double>& element_values,
                               std::vector<double>& vertex_values) {
  const std::vector<int>& cell = body.embedding.cell;
  vertex_values.resize(cell.size());
  for (size_t v = 0; v < cell.size(); ++v) vertex_values[v] = element_values[body.element_offset + cell[v]];
}

}  // namespace sinew
