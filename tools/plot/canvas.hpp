#pragma once
// A small CPU rasteriser for charts: an RGB8 image with lines, filled rectangles and
// polygons, and text (stb_easy_font glyphs, which are rectangles), written as PNG.
// Coordinates are pixels, x right, y down; a pixel (i, j) covers [i, i+1) x [j, j+1) and is
// filled when its centre (i + 0.5, j + 0.5) is inside a shape. Everything is clipped to
// the image. No anti-aliasing: charts stay exact colours, which the tests rely on.
#include <cstdint>
#include <string>
#include <vector>

namespace sinew::plot {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

struct Point {
  double x = 0, y = 0;
};

enum class Align { Left, Center, Right };

class Canvas {
 public:
  Canvas(int width, int height, Rgb background = {255, 255, 255});

  int width() const { return m_width; }
  int height() const { return m_height; }
  Rgb pixel(int x, int y) const;
  const std::vector<uint8_t>& rgb() const { return m_rgb; }  // 3 * width * height, rows top down
  // Pixels of exactly this colour.
  long count(Rgb color) const;

  void set(int x, int y, Rgb color);  // ignored outside the image
  // Pixels whose centres lie in [x0, x1) x [y0, y1) (corners in any order).
  void fill_rect(double x0, double y0, double x1, double y1, Rgb color);
  // A segment `thickness` pixels wide (square pen); dash > 0 draws `dash` pixels on, `dash` off.
  void line(Point a, Point b, Rgb color, int thickness = 1, int dash = 0);
  // Even-odd scanline fill of a closed polygon (the last point joins the first).
  void fill_polygon(const std::vector<Point>& points, Rgb color);
  // The band between two piecewise-linear curves over ascending xs (one fill per pixel
  // column, exact for the x-monotone bands of a stacked chart, any number of samples).
  void fill_between(const std::vector<double>& xs, const std::vector<double>& y_top,
                    const std::vector<double>& y_bottom, Rgb color);

  // Text in stb_easy_font's glyphs scaled by `scale` (a whole number of pixels per font
  // unit); `y` is the top of capitals, `align` places `x` at the left, centre or right end.
  void text(double x, double y, const std::string& s, Rgb color, int scale = 1,
            Align align = Align::Left);
  // The same turned 90 degrees anticlockwise (reads bottom to top), centred on (x, y).
  void text_vertical(double x, double y, const std::string& s, Rgb color, int scale = 1);
  static int text_width(const std::string& s, int scale = 1);
  static int text_height(int scale = 1) { return 7 * scale; }  // capitals and digits

 private:
  int m_width, m_height;
  std::vector<uint8_t> m_rgb;
};

// The image as PNG bytes (stb_image_write). Throws std::runtime_error.
std::string encode_png(const Canvas& canvas);
// Encodes, then writes whole or not at all (engine/io/atomic_file.hpp). Throws
// std::runtime_error naming the path.
void write_png(const std::string& path, const Canvas& canvas);

}  // namespace sinew::plot
