#pragma once
// Where the colour-map legend was drawn: pixels, from the top-left corner.
namespace sinew {

struct LegendBox {
  float x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
};

}  // namespace sinew
