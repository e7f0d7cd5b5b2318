// Colour maps: names, colours at the ends, scales, transfer to the surface.
#include <doctest/doctest.h>

#include <stdexcept>

#include "render/color_map.hpp"

using namespace sinew;

TEST_CASE("colour map: names parse, others are refused with the choices") {
  CHECK(parse_color_map("energy") == ColorMapKind::Energy);
  CHECK(parse_color_map("volume") == ColorMapKind::Volume);
  CHECK(parse_color_map("none") == ColorMapKind::None);
  CHECK_THROWS_WITH_AS(parse_color_map("strain"), doctest::Contains("energy, volume or none"), std::invalid_argument);
  CHECK(std::string(color_map_field(ColorMapKind::Energy)) == "energy_ratio");
  CHECK(std::string(color_map_field(ColorMapKind::Volume)) == "volume_ratio");
}

TEST_CASE("colour map: energy runs blue to red over a fixed [0, 1] and clamps") {
  const ColorScale s = update_scale(ColorMapKind::Energy, {0.2, 3.0}, nullptr);
  CHECK(s.lo == 0);
  CHECK(s.hi == 1);  // fixed: a value above the limit does not rescale the map
  const Eigen::Vector3f low = map_color(ColorMapKind::Energy, s, 0), high = map_color(ColorMapKind::Energy, s, 1);
  CHECK(low.z() > low.x());
  CHECK(high.x() > high.z());
  CHECK(map_color(ColorMapKind::Energy, s, 5).isApprox(high));
  CHECK(map_color(ColorMapKind::Energy, s, -1).isApprox(low));
  // Monotone brightness change is not required, but neighbouring values stay close.
  CHECK((map_color(ColorMapKind::Energy, s, 0.50) - map_color(ColorMapKind::Energy, s, 0.51)).norm() < 0.05f);
}

TEST_CASE("colour map: volume is centred on J = 1, widens to the data and never narrows") {
  const ColorScale first = update_scale(ColorMapKind::Volume, {0.98, 1.01}, nullptr);
  CHECK(first.lo == doctest::Approx(0.98));
  CHECK(first.hi == doctest::Approx(1.02));
  const ColorScale later = update_scale(ColorMapKind::Volume, {1.001}, &first);
  CHECK(later.hi == doctest::Approx(1.02));
  const ColorScale quiet = update_scale(ColorMapKind::Volume, {1.0}, nullptr);
  CHECK(quiet.hi - 1 == doctest::Approx(0.005));  // a floor, so float noise is not amplified
  const Eigen::Vector3f white = map_color(ColorMapKind::Volume, first, 1.0);
  CHECK(white.minCoeff() > 0.9f);
  CHECK(map_color(ColorMapKind::Volume, first, 0.9).z() > map_color(ColorMapKind::Volume, first, 0.9).x());
  CHECK(map_color(ColorMapKind::Volume, first, 1.1).x() > map_color(ColorMapKind::Volume, first, 1.1).z());
}

TEST_CASE("colour map: a surface vertex takes the value of the element it is embedded in") {
  Body body;
  body.element_offset = 2;
  body.embedding.cell = {1, 0, 1};
  std::vector<double> per_vertex;
  element_values_to_surface(body, {9, 9, 0.25, 0.75}, per_vertex);
  CHECK(per_vertex == std::vector<double>{0.75, 0.25, 0.75});
}
