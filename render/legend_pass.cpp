#include "render/legend_pass.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace sinew {
namespace {

const char* kVs = R"(#version 330 core
layout(location = 0) in vec2 pixel;
layout(location = 1) in vec4 rgba;
uniform vec2 size;
out vec4 v_rgba;
void main() {
  v_rgba = rgba;
  gl_Position = vec4(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0, 0.0, 1.0);
})";
const char* kFs = R"(#version 330 core
in vec4 v_rgba;
out vec4 color;
void main() { color = v_rgba; })";

constexpr int kGlyphHeight = 7;  // stb_easy_font capitals and digits, in font units

std::string label(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g", v);
  return s;
}

float text_width(std::string s) { return float(stb_easy_font_width(s.data())); }

}  // namespace

LegendPass::LegendPass() : m_program(kVs, kFs, "legend"), m_triangles({2, 4}) {}

void LegendPass::rect(float x, float y, float w, float h, const Eigen::Vector4f& top, const Eigen::Vector4f& bottom) {
  const float corners[6][2] = {{x, y}, {x + w, y}, {x + w, y + h}, {x, y}, {x + w, y + h}, {x, y + h}};
  for (const auto& c : corners) {
    const Eigen::Vector4f& rgba = c[1] == y ? top : bottom;
    m_vertices.insert(m_vertices.end(), {c[0], c[1], rgba[0], rgba[1], rgba[2], rgba[3]});
  }
}

void LegendPass::text(float x, float y, float scale, const std::string& s, const Eigen::Vector4f& color) {
  std::string copy = s;
  std::vector<char> buffer(300 * (s.size() + 1));
  // Vertices of 16 bytes (x, y, z, colour), 4 per quad; we only use x and y.
  const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), int(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    const float* v0 = reinterpret_cast<const float*>(buffer.data() + 64 * q);
    const float* v2 = reinterpret_cast<const float*>(buffer.data() + 64 * q + 32);
    rect(x + scale * v0[0], y + scale * v0[1], scale * (v2[0] - v0[0]), scale * (v2[1] - v0[1]), color, color);
  }
}

LegendBox LegendPass::draw(ColorMapKind kind, const ColorScale& scale, int width, int height) {
  m_vertices.clear();
  const float s = std::max(1.0f, std::round(height / 360.0f));  // text scale: 2 at 720p
  const float pad = 6 * s, bar_w = std::max(8.0f, 0.022f * height), bar_h = 0.42f * height;
  const std::string labels[3] = {label(scale.hi), label(0.5 * (scale.lo + scale.hi)), label(scale.lo)};
  float label_w = 0;
  for (const auto& l : labels) label_w = std::max(label_w, s * text_width(l));
  const float content_w = std::max(bar_w + 5 * s + label_w, s * text_width(scale.title));
  const float title_h = s * (kGlyphHeight + 6);
  LegendBox box{0, 0, content_w + 2 * pad, title_h + bar_h + 2 * pad + s * kGlyphHeight};
  box.x = width - 0.025f * height - box.width;
  box.y = 0.5f * (height - box.height);

  const Eigen::Vector4f panel(1, 1, 1, 0.72f), ink(0.1f, 0.1f, 0.12f, 1);
  rect(box.x, box.y, box.width, box.height, panel, panel);
  text(box.x + pad, box.y + pad, s, scale.title, ink);
  const float bar_x = box.x + pad, bar_y = box.y + pad + title_h + 0.5f * s * kGlyphHeight;
  constexpr int kSegments = 48;  // fine enough that the piecewise-linear map looks continuous
  for (int i = 0; i < kSegments; ++i) {
    const double top_v = scale.hi - (scale.hi - scale.lo) * i / kSegments;
    const double bottom_v = scale.hi - (scale.hi - scale.lo) * (i + 1) / kSegments;
    Eigen::Vector4f top, bottom;
    top << map_color(kind, scale, top_v), 1;
    bottom << map_color(kind, scale, bottom_v), 1;
    rect(bar_x, bar_y + bar_h * i / kSegments, bar_w, bar_h / kSegments, top, bottom);
  }
  const float line = std::max(1.0f, 0.5f * s);
  rect(bar_x - line, bar_y - line, bar_w + 2 * line, line, ink, ink);
  rect(bar_x - line, bar_y + bar_h, bar_w + 2 * line, line, ink, ink);
  rect(bar_x - line, bar_y, line, bar_h, ink, ink);
  rect(bar_x + bar_w, bar_y, line, bar_h, ink, ink);
  for (int i = 0; i < 3; ++i) {
    const float y = bar_y + bar_h * i / 2;
    rect(bar_x + bar_w, y - 0.5f * line, 3 * s, line, ink, ink);
    text(bar_x + bar_w + 5 * s, y - 0.5f * s * kGlyphHeight, s, labels[i], ink);
  }

  m_triangles.set_vertices(m_vertices);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  m_program.use();
  m_program.set("size", Eigen::Vector2f(float(width), float(height)));
  m_triangles.draw(GL_TRIANGLES);
  glDisable(GL_BLEND);
  return box;
}

}  // namespace sinew
