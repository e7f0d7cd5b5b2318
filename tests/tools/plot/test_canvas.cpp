// The chart rasteriser: which pixels each primitive fills, text placement, PNG output.
#include <doctest/doctest.h>

#include <stb/stb_image.h>

#include <filesystem>

#include "tests/support/cli_runner.hpp"
#include "tools/plot/canvas.hpp"

using sinew::plot::Align;
using sinew::plot::Canvas;
using sinew::plot::Point;
using sinew::plot::Rgb;

namespace {
constexpr Rgb kWhite{255, 255, 255}, kRed{200, 30, 30}, kBlue{30, 30, 200};

// Bounding box of the pixels of one colour: {x0, y0, x1, y1}, exclusive ends; empty: all -1.
std::array<int, 4> bounds(const Canvas& c, Rgb color) {
  std::array<int, 4> b{-1, -1, -1, -1};
  for (int y = 0; y < c.height(); ++y)
    for (int x = 0; x < c.width(); ++x)
      if (c.pixel(x, y) == color) {
        if (b[0] < 0) b = {x, y, x + 1, y + 1};
        b = {std::min(b[0], x), std::min(b[1], y), std::max(b[2], x + 1), std::max(b[3], y + 1)};
      }
  return b;
}
}  // namespace

TEST_CASE("canvas: starts as the background colour") {
  Canvas c(7, 5, kBlue);
  CHECK(c.count(kBlue) == 35);
  CHECK(c.rgb().size() == 3u * 35);
  CHECK_THROWS(Canvas(0, 5));
}

TEST_CASE("canvas: fill_rect fills the pixels whose centres are inside, clipped to the image") {
  Canvas c(10, 10);
  c.fill_rect(1, 1, 3, 3, kRed);
  CHECK(c.count(kRed) == 4);
  CHECK(bounds(c, kRed) == std::array<int, 4>{1, 1, 3, 3});
  // Corners in any order; half-pixel edges: centres 2.5..4.5 are inside [2.4, 4.6).
  c.fill_rect(4.6, 4.6, 2.4, 2.4, kBlue);
  CHECK(c.count(kBlue) == 9);
  Canvas d(4, 4);
  d.fill_rect(-10, -10, 100, 100, kRed);
  CHECK(d.count(kRed) == 16);
}

TEST_CASE("canvas: lines are continuous, one pixel wide, and dashes leave gaps") {
  Canvas c(20, 20);
  c.line({0.5, 5.5}, {9.5, 5.5}, kRed);
  CHECK(c.count(kRed) == 10);
  CHECK(bounds(c, kRed) == std::array<int, 4>{0, 5, 10, 6});
  // A diagonal touches every column and every row once.
  Canvas d(20, 20);
  d.line({0.5, 0.5}, {19.5, 19.5}, kRed);
  CHECK(d.count(kRed) == 20);
  for (int i = 0; i < 20; ++i) CHECK(d.pixel(i, i) == kRed);
  Canvas e(20, 20);
  e.line({0.5, 5.5}, {19.5, 5.5}, kRed, 1, 3);
  CHECK(e.count(kRed) > 6);
  CHECK(e.count(kRed) < 14);
  Canvas f(20, 20);
  f.line({2.0, 10.0}, {18.0, 10.0}, kRed, 3);
  CHECK(bounds(f, kRed)[3] - bounds(f, kRed)[1] == 3);
}

TEST_CASE("canvas: polygons fill like rectangles and triangles cover half their box") {
  Canvas c(40, 40);
  c.fill_polygon({{2, 3}, {12, 3}, {12, 9}, {2, 9}}, kRed);
  Canvas d(40, 40);
  d.fill_rect(2, 3, 12, 9, kRed);
  CHECK(c.rgb() == d.rgb());

  Canvas t(40, 40);
  t.fill_polygon({{0, 0}, {40, 0}, {0, 40}}, kBlue);
  CHECK(std::abs(t.count(kBlue) - 800) <= 40);
  // Even-odd: a square with a square hole.
  Canvas h(40, 40);
  h.fill_polygon({{0, 0}, {30, 0}, {30, 30}, {0, 30}, {0, 0}, {10, 10}, {20, 10}, {20, 20}, {10, 20}, {10, 10}}, kRed);
  CHECK(h.pixel(15, 15) == kWhite);
  CHECK(h.pixel(5, 5) == kRed);
  CHECK(h.count(kRed) == 900 - 100);
}

TEST_CASE("canvas: fill_between covers the band and keeps spikes narrower than a pixel") {
  Canvas c(20, 20);
  // A band from y = 10 to 15 over x in [2, 12].
  c.fill_between({2, 12}, {10, 10}, {15, 15}, kRed);
  CHECK(c.count(kRed) == 50);
  CHECK(bounds(c, kRed) == std::array<int, 4>{2, 10, 12, 15});
  // Thousands of samples per pixel: one spike at x = 5.3 still reaches the top.
  std::vector<double> xs, top, bottom;
  for (int i = 0; i <= 2000; ++i) {
    xs.push_back(i * 0.01);
    top.push_back(i == 530 ? 1.0 : 18.0);
    bottom.push_back(20.0);
  }
  Canvas s(20, 20);
  s.fill_between(xs, top, bottom, kBlue);
  CHECK(s.pixel(5, 1) == kBlue);
  CHECK(s.pixel(4, 1) == kWhite);
  CHECK(s.pixel(6, 1) == kWhite);
  CHECK(s.pixel(10, 19) == kBlue);
}

TEST_CASE("canvas: text lies where it is placed, at the given scale and alignment") {
  const std::string s = "p95 12.5 ms";
  CHECK(Canvas::text_width(s, 2) == 2 * Canvas::text_width(s, 1));
  CHECK(Canvas::text_height(3) == 21);

  Canvas c(200, 60);
  c.text(10, 20, "E10", kRed, 2);
  const auto b = bounds(c, kRed);
  CHECK(b[0] == 10);
  CHECK(b[1] == 20);
  CHECK(b[3] == 20 + Canvas::text_height(2));  // capitals and digits only
  CHECK(b[2] <= 10 + Canvas::text_width("E10", 2));

  Canvas r(200, 60);
  r.text(150, 20, "E10", kRed, 2, Align::Right);
  CHECK(bounds(r, kRed)[2] <= 150);
  CHECK(bounds(r, kRed)[2] >= 150 - 2 * 2);
  Canvas m(200, 60);
  m.text(100, 20, "E10", kRed, 2, Align::Center);
  const auto mb = bounds(m, kRed);
  CHECK(std::abs((mb[0] + mb[2]) / 2 - 100) <= 3);

  // Turned: taller than wide, centred on the point.
  Canvas v(60, 200);
  v.text_vertical(30, 100, "E10 MS", kBlue, 2);
  const auto vb = bounds(v, kBlue);
  CHECK(vb[3] - vb[1] > vb[2] - vb[0]);
  CHECK(std::abs((vb[1] + vb[3]) / 2 - 100) <= 3);
  CHECK(std::abs((vb[0] + vb[2]) / 2 - 30) <= 3);
}

TEST_CASE("canvas: PNG round trip and atomic write") {
  Canvas c(33, 17, kBlue);
  c.fill_rect(3, 4, 9, 12, kRed);
  const std::string png = sinew::plot::encode_png(c);
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()), int(png.size()), &w,
                                              &h, &channels, 3);
  REQUIRE(data);
  CHECK(w == 33);
  CHECK(h == 17);
  CHECK(std::equal(c.rgb().begin(), c.rgb().end(), data));
  stbi_image_free(data);

  sinew::test::TempDir dir("canvas_png");
  sinew::plot::write_png(dir / "a.png", c);
  CHECK(std::filesystem::file_size(dir / "a.png") == png.size());
  CHECK_THROWS_WITH(sinew::plot::write_png(dir / "missing/b.png", c), doctest::Contains("missing/b.png"));
  CHECK(!std::filesystem::exists(dir / "missing"));
}
