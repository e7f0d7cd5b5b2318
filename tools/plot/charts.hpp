#pragma once
// Charts drawn on a Canvas: stacked series over samples (per-stage times over a run), a
// histogram, and an x-y line/scatter chart with linear or logarithmic axes (work-precision
// plots). Each draws inside a rectangle of the canvas: title, framed plot area, ticks with
// labels, axis labels, legend.
#include <string>
#include <vector>

#include "tools/plot/canvas.hpp"

namespace sinew::plot {

struct Rect {
  int x = 0, y = 0, width = 0, height = 0;
};

// The i-th colour of a fixed palette of 12 distinguishable colours (then repeats): the
// profile chart draws 10 stages and the untimed rest.
Rgb series_color(int i);
inline constexpr Rgb kInk{30, 30, 36};         // text, frame, ticks
inline constexpr Rgb kGrid{225, 225, 230};     // grid lines
inline constexpr Rgb kBackground{255, 255, 255};

// "Nice" tick values (1, 2 or 5 times a power of ten apart) covering [lo, hi], at most
// about `max_ticks` of them; all lie within [lo, hi].
std::vector<double> linear_ticks(double lo, double hi, int max_ticks);
// Powers of ten within [lo, hi] (lo > 0); with fewer than three, also 2x and 5x each decade.
std::vector<double> log_ticks(double lo, double hi);
// A short label for a tick value ("0", "0.5", "250", "1e-06").
std::string tick_label(double v);

struct StackedChart {
  std::string title, x_label, y_label;
  std::vector<double> x;                     // sample positions, ascending (e.g. frame numbers)
  std::vector<std::string> names;            // one per series, bottom first
  std::vector<std::vector<double>> values;   // values[series][sample] >= 0; non-finite counts as 0
  int text_scale = 2;
};
// Few samples (at least 4 pixels each): stacked bars; more: stacked areas. Series colours
// are series_color(0...), the legend on the right lists the top series first.
void draw_stacked(Canvas& canvas, Rect area, const StackedChart& chart);

struct Marker {
  std::string label;  // e.g. "median"
  double x = 0;
};

struct Histogram {
  std::string title, x_label, y_label = "count";
  std::vector<double> samples;  // non-finite ones are left out
  int bins = 0;                 // 0: about sqrt(n), between 5 and 40
  Rgb color = series_color(0);
  std::vector<Marker> markers;  // dashed vertical lines with their labels
  int text_scale = 2;
};
void draw_histogram(Canvas& canvas, Rect area, const Histogram& chart);

struct Series {
  std::string name;
  std::vector<double> x, y;
  bool lines = true, markers = true;
};

// Where a line chart puts its legend: over the top-right corner of the plot, in a column
// right of the plot (which then narrows; nothing is covered), or nowhere (e.g. a second
// chart whose series are the first's).
enum class LegendPlace { Inside, Right, None };

struct LineChart {
  std::string title, x_label, y_label;
  std::vector<Series> series;  // colour and marker shape (square, triangle, diamond) by index
  bool log_x = true, log_y = true;  // points with a non-positive coordinate on a log axis are left out
  LegendPlace legend = LegendPlace::Inside;
  int text_scale = 2;
};
void draw_line_chart(Canvas& canvas, Rect area, const LineChart& chart);

}  // namespace sinew::plot
