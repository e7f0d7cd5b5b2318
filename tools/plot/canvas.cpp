#include "tools/plot/canvas.hpp"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include "engine/io/atomic_file.hpp"

namespace sinew::plot {

namespace {

// First pixel index whose centre is >= v.
int first_at_or_after(double v) { return static_cast<int>(std::ceil(v - 0.5)); }

// Calls quad(x0, y0, x1, y1) for each rectangle of the glyphs of `s`, in font units.
template <class Quad>
void for_each_glyph_quad(const std::string& s, Quad quad) {
  std::string copy = s;
  std::vector<char> buffer(300 * (s.size() + 1));  // the header's worst case is ~270 per char
  const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), int(buffer.size()));
  // 4 vertices of 16 bytes (x, y, z, rgba) per quad; vertex 0 is top-left, 2 bottom-right.
  for (int q = 0; q < quads; ++q) {
    const float* v0 = reinterpret_cast<const float*>(buffer.data() + 64 * q);
    const float* v2 = reinterpret_cast<const float*>(buffer.data() + 64 * q + 32);
    quad(v0[0], v0[1], v2[0], v2[1]);
  }
}

}  // namespace

Canvas::Canvas(int width, int height, Rgb background) : m_width(width), m_height(height) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("canvas size must be positive, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  m_rgb.resize(3 * static_cast<size_t>(width) * height);
  for (size_t i = 0; i < m_rgb.size(); i += 3) {
    m_rgb[i] = background.r;
    m_rgb[i + 1] = background.g;
    m_rgb[i + 2] = background.b;
  }
}

Rgb Canvas::pixel(int x, int y) const {
  const uint8_t* p = &m_rgb[3 * (static_cast<size_t>(y) * m_width + x)];
  return {p[0], p[1], p[2]};
}

long Canvas::count(Rgb color) const {
  long n = 0;
  for (size_t i = 0; i < m_rgb.size(); i += 3)
    n += m_rgb[i] == color.r && m_rgb[i + 1] == color.g && m_rgb[i + 2] == color.b;
  return n;
}

void Canvas::set(int x, int y, Rgb color) {
  if (x < 0 || y < 0 || x >= m_width || y >= m_height) return;
  uint8_t* p = &m_rgb[3 * (static_cast<size_t>(y) * m_width + x)];
  p[0] = color.r;
  p[1] = color.g;
  p[2] = color.b;
}

void Canvas::fill_rect(double x0, double y0, double x1, double y1, Rgb color) {
  if (x1 < x0) std::swap(x0, x1);
  if (y1 < y0) std::swap(y0, y1);
  const int i0 = std::max(0, first_at_or_after(x0)), i1 = std::min(m_width, first_at_or_after(x1));
  const int j0 = std::max(0, first_at_or_after(y0)), j1 = std::min(m_height, first_at_or_after(y1));
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) set(i, j, color);
}

void Canvas::line(Point a, Point b, Rgb color, int thickness, int dash) {
  // DDA: one pen stamp per pixel of the longer axis.
  const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))));
  const double half = 0.5 * thickness;
  for (int k = 0; k <= steps; ++k) {
    if (dash > 0 && (k / dash) % 2 == 1) continue;
    const double t = static_cast<double>(k) / steps;
    const double x = a.x + t * (b.x - a.x), y = a.y + t * (b.y - a.y);
    fill_rect(x - half, y - half, x + half, y + half, color);
  }
}

void Canvas::fill_polygon(const std::vector<Point>& points, Rgb color) {
  if (points.size() < 3) return;
  double y_lo = points[0].y, y_hi = points[0].y;
  for (const Point& p : points) y_lo = std::min(y_lo, p.y), y_hi = std::max(y_hi, p.y);
  std::vector<double> crossings;
  for (int j = std::max(0, first_at_or_after(y_lo)); j < std::min(m_height, first_at_or_after(y_hi)); ++j) {
    const double yc = j + 0.5;
    crossings.clear();
    for (size_t k = 0; k < points.size(); ++k) {
      const Point& p = points[k];
      const Point& q = points[(k + 1) % points.size()];
      // Half-open in y so that a vertex on the scanline counts once.
      if ((p.y <= yc && yc < q.y) || (q.y <= yc && yc < p.y))
        crossings.push_back(p.x + (yc - p.y) / (q.y - p.y) * (q.x - p.x));
    }
    std::sort(crossings.begin(), crossings.end());
    for (size_t k = 0; k + 1 < crossings.size(); k += 2) fill_rect(crossings[k], j, crossings[k + 1], j + 1, color);
  }
}

void Canvas::fill_between(const std::vector<double>& xs, const std::vector<double>& y_top,
                          const std::vector<double>& y_bottom, Rgb color) {
  const size_t n = xs.size();
  if (n == 0 || y_top.size() != n || y_bottom.size() != n) return;
  auto at = [&](const std::vector<double>& y, size_t k, double x) {
    if (k + 1 >= n || xs[k + 1] == xs[k]) return y[k];
    return y[k] + (x - xs[k]) / (xs[k + 1] - xs[k]) * (y[k + 1] - y[k]);
  };
  // Each column [i, i+1) gets the union of the band over it, so that a spike between two
  // column centres (thousands of frames on a few hundred pixels) still shows.
  size_t k = 0;
  const int i_begin = static_cast<int>(std::floor(xs[0]));
  const int i_end = std::min(m_width - 1, std::max(i_begin, static_cast<int>(std::ceil(xs[n - 1])) - 1));
  for (int i = std::max(0, i_begin); i <= i_end; ++i) {
    const double a = std::max(xs[0], double(i)), b = std::min(xs[n - 1], i + 1.0);
    while (k + 1 < n && xs[k + 1] < a) ++k;
    double top = at(y_top, k, a), bottom = at(y_bottom, k, a);
    size_t m = k;
    for (; m + 1 < n && xs[m + 1] <= b; ++m) {
      top = std::min(top, y_top[m + 1]);
      bottom = std::max(bottom, y_bottom[m + 1]);
    }
    top = std::min(top, at(y_top, m, b));
    bottom = std::max(bottom, at(y_bottom, m, b));
    fill_rect(i, top, i + 1, bottom, color);
  }
}

int Canvas::text_width(const std::string& s, int scale) {
  float right = 0;
  for_each_glyph_quad(s, [&](float, float, float x1, float) { right = std::max(right, x1); });
  return static_cast<int>(std::ceil(right)) * scale;
}

void Canvas::text(double x, double y, const std::string& s, Rgb color, int scale, Align align) {
  const double w = text_width(s, scale);
  const double left = align == Align::Left ? x : align == Align::Center ? x - 0.5 * w : x - w;
  for_each_glyph_quad(s, [&](float x0, float y0, float x1, float y1) {
    fill_rect(left + scale * x0, y + scale * y0, left + scale * x1, y + scale * y1, color);
  });
}

void Canvas::text_vertical(double x, double y, const std::string& s, Rgb color, int scale) {
  // Font (u right, v down) -> image (x0 + v, y0 - u): the baseline runs upwards.
  const double x0 = x - 0.5 * text_height(scale), y0 = y + 0.5 * text_width(s, scale);
  for_each_glyph_quad(s, [&](float u0, float v0, float u1, float v1) {
    fill_rect(x0 + scale * v0, y0 - scale * u1, x0 + scale * v1, y0 - scale * u0, color);
  });
}

std::string encode_png(const Canvas& canvas) {
  std::string png;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
  };
  if (!stbi_write_png_to_func(append, &png, canvas.width(), canvas.height(), 3, canvas.rgb().data(),
                              3 * canvas.width()))
    throw std::runtime_error("PNG encoding failed");
  return png;
}

void write_png(const std::string& path, const Canvas& canvas) {
  std::string png;
  try {
    png = encode_png(canvas);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write '" + path + "': " + e.what());
  }
  write_file_atomically(path, [&](std::ostream& out) { out.write(png.data(), static_cast<std::streamsize>(png.size())); });
}

}  // namespace sinew::plot
