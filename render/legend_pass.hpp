#pragma once
// The colour-map legend: a vertical gradient bar at the right edge with the scale's ends and
// middle labelled and the map's title above, on a translucent panel. Text uses
// stb_easy_font (glyphs made of quads, no texture).
#include <string>
#include <vector>

#include "render/color_map.hpp"
#include "render/gl_program.hpp"
#include "render/gl_vertex_array.hpp"
#include "render/legend_box.hpp"

namespace sinew {

class LegendPass {
 public:
  LegendPass();
  // Returns where the legend was drawn.
  LegendBox draw(ColorMapKind kind, const ColorScale& scale, int width, int height);

 private:
  GlProgram m_program;
  GlVertexArray m_triangles;
  std::vector<float> m_vertices;  // x, y, r, g, b, a per vertex, pixels
  void rect(float x, float y, float w, float h, const Eigen::Vector4f& top, const Eigen::Vector4f& bottom);
  void text(float x, float y, float scale, const std::string& s, const Eigen::Vector4f& color);
};

}  // namespace sinew
