// Charts: tick choice, and that each chart draws its series in their colours, in proportion.
#include <doctest/doctest.h>

#include <cmath>

#include "tools/plot/charts.hpp"

namespace plot = sinew::plot;
using plot::Canvas;

namespace {
// Pixels of `color` in column x.
int column_count(const Canvas& c, int x, plot::Rgb color) {
  int n = 0;
  for (int y = 0; y < c.height(); ++y) n += c.pixel(x, y) == color;
  return n;
}
}  // namespace

TEST_CASE("charts: linear ticks are 1, 2 or 5 times a power of ten, within the range") {
  CHECK(plot::linear_ticks(0, 10, 6) == std::vector<double>{0, 2, 4, 6, 8, 10});
  CHECK(plot::linear_ticks(0, 1, 3) == std::vector<double>{0, 0.5, 1});
  const auto t = plot::linear_ticks(0.13, 0.97, 5);
  CHECK(t.front() >= 0.13);
  CHECK(t.back() <= 0.97);
  REQUIRE(t.size() == 4);  // 0.2, 0.4, 0.6, 0.8
  CHECK(t[3] == doctest::Approx(0.8));
  CHECK(plot::tick_label(t[0]) == "0.2");
  CHECK(plot::tick_label(3 * 0.1) == "0.3");
  CHECK(plot::tick_label(-1e-17) == "0");
  CHECK(plot::linear_ticks(5, 5, 4) == std::vector<double>{5});
}

TEST_CASE("charts: log ticks are the decades, with 2 and 5 when there are few") {
  CHECK(plot::log_ticks(1e-6, 1e-1).size() == 6);
  CHECK(plot::tick_label(plot::log_ticks(1e-6, 1e-1)[0]) == "1e-06");
  CHECK(plot::log_ticks(1, 10) == std::vector<double>{1, 2, 5, 10});
  CHECK(plot::log_ticks(3, 300) == std::vector<double>{5, 10, 20, 50, 100, 200});
  CHECK(plot::log_ticks(0, 10).empty());
}

TEST_CASE("charts: stacked areas stack in proportion, each series in its colour") {
  plot::StackedChart chart;
  chart.title = "T";
  chart.names = {"a", "b"};
  for (int i = 0; i < 500; ++i) chart.x.push_back(i);
  chart.values = {std::vector<double>(500, 1.0), std::vector<double>(500, 3.0)};
  Canvas c(800, 400);
  plot::draw_stacked(c, {0, 0, 800, 400}, chart);
  const long a = c.count(plot::series_color(0)), b = c.count(plot::series_color(1));
  // The legend swatches add a few pixels of each colour.
  CHECK(a > 1000);
  CHECK(b == doctest::Approx(3.0 * a).epsilon(0.1));
  // Series b lies on top of a in every column of the plot.
  int x = 400, top_a = -1, top_b = -1;
  for (int y = 0; y < c.height(); ++y) {
    if (top_a < 0 && c.pixel(x, y) == plot::series_color(0)) top_a = y;
    if (top_b < 0 && c.pixel(x, y) == plot::series_color(1)) top_b = y;
  }
  CHECK(top_b < top_a);
}

TEST_CASE("charts: a few samples are drawn as separate stacked bars; null values count as 0") {
  plot::StackedChart chart;
  chart.names = {"a"};
  chart.x = {1, 2, 3};
  chart.values = {{1.0, NAN, 2.0}};
  Canvas c(600, 300);
  plot::draw_stacked(c, {0, 0, 600, 300}, chart);
  // Three bars: count the runs of bar colour along a row near the bottom of the plot.
  int runs = 0;
  bool in = false;
  const int y = 300 - 60;
  for (int x = 0; x < 600; ++x) {
    const bool here = c.pixel(x, y) == plot::series_color(0);
    runs += here && !in;
    in = here;
  }
  CHECK(runs == 2);  // the middle frame has no height
}

TEST_CASE("charts: histogram bar heights follow the counts") {
  plot::Histogram h;
  h.samples = {1, 1, 1, 2, NAN};
  h.bins = 2;
  h.color = {10, 200, 10};
  h.markers = {{"median", 1.0}};
  Canvas c(400, 300);
  plot::draw_histogram(c, {0, 0, 400, 300}, h);
  int tall = 0, low = 0;
  for (int x = 0; x < 400; ++x) {
    const int n = column_count(c, x, h.color);
    if (n > 0 && (tall == 0 || n > tall)) tall = std::max(tall, n);
  }
  for (int x = 399; x >= 0 && !low; --x) low = column_count(c, x, h.color);
  CHECK(tall == doctest::Approx(3.0 * low).epsilon(0.05));
}

TEST_CASE("charts: log-log line chart draws every series and stays inside its area") {
  plot::LineChart chart;
  chart.title = "work-precision";
  chart.x_label = "ms per step";
  chart.y_label = "error";
  for (int k = 0; k < 3; ++k) {
    plot::Series s;
    s.name = "method " + std::to_string(k);
    for (double x : {1.0, 10.0, 100.0, 1000.0}) {
      s.x.push_back(x * (k + 1));
      s.y.push_back(std::pow(x, -1.0 - k));
    }
    s.x.push_back(-1);  // not drawable on a log axis: left out
    s.y.push_back(1);
    chart.series.push_back(s);
  }
  Canvas c(700, 500, {0, 0, 0});
  plot::draw_line_chart(c, {50, 50, 600, 400}, chart);
  for (int k = 0; k < 3; ++k) CHECK(c.count(plot::series_color(k)) > 50);
  // Nothing outside the area.
  for (int y = 0; y < c.height(); ++y)
    for (int x = 0; x < c.width(); ++x)
      if (x < 50 || x >= 650 || y < 50 || y >= 450) REQUIRE(c.pixel(x, y) == plot::Rgb{0, 0, 0});
}

TEST_CASE("charts: a line chart's legend inside, in a column on the right, or none") {
  plot::LineChart chart;
  plot::Series s;
  s.name = "only series";
  s.x = {1, 10};
  s.y = {1, 10};
  s.lines = s.markers = false;  // so that only the legend could draw the series colour
  chart.series.push_back(s);
  Canvas inside(600, 400), right(600, 400), none(600, 400);
  plot::draw_line_chart(inside, {0, 0, 600, 400}, chart);
  chart.legend = plot::LegendPlace::Right;
  plot::draw_line_chart(right, {0, 0, 600, 400}, chart);
  chart.legend = plot::LegendPlace::None;
  plot::draw_line_chart(none, {0, 0, 600, 400}, chart);
  CHECK(inside.count(plot::series_color(0)) > 0);
  CHECK(none.count(plot::series_color(0)) == 0);
  // On the right: the swatch is drawn in the column beside the plot (the name is short, so
  // the column is narrow): all of it in the right third of the canvas.
  long left_part = 0, total = 0;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 600; ++x)
      if (right.pixel(x, y) == plot::series_color(0)) {
        ++total;
        left_part += x < 400;
      }
  CHECK(total > 0);
  CHECK(left_part == 0);
}
