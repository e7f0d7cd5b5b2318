#include "tools/plot/charts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace sinew::plot {

namespace {

constexpr Rgb kPalette[] = {{46, 107, 176}, {230, 126, 34},  {46, 160, 67},  {200, 50, 50},
                            {142, 94, 178}, {140, 86, 75},   {220, 110, 180}, {110, 110, 110},
                            {175, 175, 35}, {30, 180, 190}, {20, 60, 110},  {250, 190, 120}};

// Maps data to pixels inside `plot`; log axes map log10 of the value.
struct Axes {
  Rect plot;
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  bool log_x = false, log_y = false;

  double fx(double x) const { return log_x ? std::log10(x) : x; }
  double fy(double y) const { return log_y ? std::log10(y) : y; }
  double px(double x) const {
    return plot.x + (fx(x) - fx(x_lo)) / (fx(x_hi) - fx(x_lo)) * plot.width;
  }
  double py(double y) const {
    return plot.y + plot.height - (fy(y) - fy(y_lo)) / (fy(y_hi) - fy(y_lo)) * plot.height;
  }
};

// A tick step of 1, 2 or 5 times a power of ten, at least `raw`.
double nice_step(double raw) {
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= raw * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

// [lo, hi] widened to whole tick steps; a flat range is opened around its value.
void nice_range(double& lo, double& hi, int max_ticks, bool integer_steps = false) {
  if (!(hi > lo)) {
    const double pad = lo == 0 ? 1 : 0.5 * std::abs(lo);
    lo -= lo == 0 ? 0 : pad;
    hi += pad;
  }
  double step = nice_step((hi - lo) / std::max(1, max_ticks - 1));
  if (integer_steps) step = std::max(step, 1.0);
  lo = std::floor(lo / step + 1e-9) * step;
  hi = std::ceil(hi / step - 1e-9) * step;
}

void log_range(double& lo, double& hi) {
  lo = std::pow(10.0, std::floor(std::log10(lo) + 1e-9));
  hi = std::pow(10.0, std::ceil(std::log10(hi) - 1e-9));
  if (hi <= lo) hi = lo * 10;
}

struct Margins {
  int left = 0, right = 0, top = 0, bottom = 0;
};

// The plot rectangle inside `area`, leaving room for the title, the tick labels and axis
// labels, and a legend column of `legend_width` on the right.
Rect layout(Rect area, int scale, int y_tick_label_width, int legend_width) {
  const int th = Canvas::text_height(scale), pad = 4 * scale;
  Margins m;
  m.top = th + 3 * pad;
  m.left = pad + th + pad + y_tick_label_width + pad + 2 * scale;
  m.bottom = 2 * scale + pad + th + pad + th + pad;
  m.right = legend_width > 0 ? legend_width + 5 * pad : 3 * pad;  // 3 pads before the legend, 2 after
  return {area.x + m.left, area.y + m.top, std::max(1, area.width - m.left - m.right),
          std::max(1, area.height - m.top - m.bottom)};
}

int max_label_width(const std::vector<double>& ticks, int scale) {
  int w = 0;
  for (double t : ticks) w = std::max(w, Canvas::text_width(tick_label(t), scale));
  return w;
}

// Linear ticks over [lo, hi] as many as fit along `pixels` with room between their labels.
std::vector<double> fitting_ticks(double lo, double hi, int pixels, int scale) {
  for (int max_ticks = 12;; --max_ticks) {
    std::vector<double> ticks = linear_ticks(lo, hi, max_ticks);
    const int room = max_label_width(ticks, scale) + 4 * Canvas::text_height(scale);
    if (max_ticks <= 2 || static_cast<int>(ticks.size()) * room <= pixels) return ticks;
  }
}

// Snapped to a pixel centre, so that 1-pixel lines are crisp.
double snap(double v) { return std::floor(v) + 0.5; }

// Grid, frame, ticks, tick labels, title and axis labels.
void draw_axes(Canvas& c, Rect area, const Axes& ax, const std::vector<double>& x_ticks,
               const std::vector<double>& y_ticks, const std::string& title, const std::string& x_label,
               const std::string& y_label, int scale) {
  const Rect& p = ax.plot;
  const int th = Canvas::text_height(scale), pad = 4 * scale, tick = 2 * scale;
  for (double t : x_ticks) c.line({snap(ax.px(t)), double(p.y)}, {snap(ax.px(t)), double(p.y + p.height)}, kGrid);
  for (double t : y_ticks) c.line({double(p.x), snap(ax.py(t))}, {double(p.x + p.width), snap(ax.py(t))}, kGrid);
  for (double t : x_ticks) {
    const double x = snap(ax.px(t));
    c.line({x, double(p.y + p.height)}, {x, double(p.y + p.height + tick)}, kInk);
    // Centred under the tick, but kept inside the area.
    const double half = 0.5 * Canvas::text_width(tick_label(t), scale);
    const double centre = std::clamp(x, area.x + half, area.x + area.width - half);
    c.text(centre, p.y + p.height + tick + pad, tick_label(t), kInk, scale, Align::Center);
  }
  for (double t : y_ticks) {
    const double y = snap(ax.py(t));
    c.line({double(p.x - tick), y}, {double(p.x), y}, kInk);
    c.text(p.x - tick - pad, y - 0.5 * th, tick_label(t), kInk, scale, Align::Right);
  }
  // Frame: the four edges of the plot rectangle, on its outermost pixels.
  const double l = p.x + 0.5, r = p.x + p.width - 0.5, t = p.y + 0.5, b = p.y + p.height - 0.5;
  c.line({l, t}, {r, t}, kInk);
  c.line({l, b}, {r, b}, kInk);
  c.line({l, t}, {l, b}, kInk);
  c.line({r, t}, {r, b}, kInk);
  c.text(area.x + 0.5 * area.width, area.y + pad, title, kInk, scale, Align::Center);
  c.text(p.x + 0.5 * p.width, p.y + p.height + tick + pad + th + pad, x_label, kInk, scale, Align::Center);
  c.text_vertical(area.x + pad + 0.5 * th, p.y + 0.5 * p.height, y_label, kInk, scale);
}

// Legend entries top to bottom: a colour swatch and the name, from (x, y).
void draw_legend(Canvas& c, double x, double y, const std::vector<std::pair<std::string, Rgb>>& entries,
                 int scale) {
  const int th = Canvas::text_height(scale), gap = 2 * th;
  for (size_t k = 0; k < entries.size(); ++k) {
    const double row = y + k * gap;
    c.fill_rect(x, row - 0.5 * scale, x + 1.5 * th, row + th + 0.5 * scale, entries[k].second);
    c.text(x + 1.5 * th + 3 * scale, row, entries[k].first, kInk, scale);
  }
}

int legend_width(const std::vector<std::string>& names, int scale) {
  int w = 0;
  for (const std::string& n : names) w = std::max(w, Canvas::text_width(n, scale));
  return names.empty() ? 0 : w + static_cast<int>(1.5 * Canvas::text_height(scale)) + 3 * scale;
}

double finite_or_zero(double v) { return std::isfinite(v) ? v : 0; }

}  // namespace

Rgb series_color(int i) {
  constexpr int n = sizeof kPalette / sizeof kPalette[0];
  return kPalette[((i % n) + n) % n];
}

std::vector<double> linear_ticks(double lo, double hi, int max_ticks) {
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return {lo};
  // The finest step of 1, 2 or 5 times a power of ten that gives at most max_ticks ticks.
  double step = nice_step((hi - lo) / std::max(1, max_ticks) / 10);
  auto count = [&](double s) { return std::floor(hi / s + 1e-9) - std::ceil(lo / s - 1e-9) + 1; };
  while (count(step) > std::max(1, max_ticks)) step = nice_step(step * 1.5);
  std::vector<double> ticks;
  // Integer multiples of the step, so that labels do not collect rounding errors.
  for (long k = static_cast<long>(std::ceil(lo / step - 1e-9)); k <= static_cast<long>(std::floor(hi / step + 1e-9)); ++k)
    ticks.push_back(k * step == 0 ? 0.0 : k * step);
  return ticks;
}

std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> decades, all;
  if (!(lo > 0) || !(hi >= lo)) return decades;
  for (int e = static_cast<int>(std::ceil(std::log10(lo) - 1e-9)); e <= static_cast<int>(std::floor(std::log10(hi) + 1e-9)); ++e)
    decades.push_back(std::pow(10.0, e));
  if (decades.size() >= 3) return decades;
  for (int e = static_cast<int>(std::floor(std::log10(lo))); e <= static_cast<int>(std::ceil(std::log10(hi))); ++e)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, e);
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) all.push_back(v);
    }
  return all;
}

std::string tick_label(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return s;
}

void draw_stacked(Canvas& c, Rect area, const StackedChart& chart) {
  const int scale = chart.text_scale;
  const size_t n = chart.x.size(), layers = chart.values.size();
  std::vector<std::vector<double>> top(layers, std::vector<double>(n, 0));  // cumulative sums
  double y_hi = 0;
  for (size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (size_t s = 0; s < layers; ++s) {
      sum += i < chart.values[s].size() ? std::max(0.0, finite_or_zero(chart.values[s][i])) : 0;
      top[s][i] = sum;
    }
    y_hi = std::max(y_hi, sum);
  }
  double y_lo = 0;
  nice_range(y_lo, y_hi, 6);
  y_lo = 0;
  const std::vector<double> y_ticks = linear_ticks(y_lo, y_hi, 6);
  std::vector<std::string> legend_names(chart.names.rbegin(), chart.names.rend());
  Axes ax;
  ax.plot = layout(area, scale, max_label_width(y_ticks, scale), legend_width(legend_names, scale));
  ax.y_lo = y_lo;
  ax.y_hi = y_hi;
  const double spacing = n > 1 ? (chart.x.back() - chart.x.front()) / (n - 1) : 1;
  const bool bars = n > 0 && ax.plot.width >= 4.0 * n;
  ax.x_lo = n ? chart.x.front() - (bars ? 0.5 * spacing : 0) : 0;
  ax.x_hi = n ? chart.x.back() + (bars ? 0.5 * spacing : 0) : 1;
  if (!(ax.x_hi > ax.x_lo)) ax.x_hi = ax.x_lo + 1;
  std::vector<double> x_ticks = fitting_ticks(ax.x_lo, ax.x_hi, ax.plot.width, scale);
  if (bars)  // whole samples only
    x_ticks.erase(std::remove_if(x_ticks.begin(), x_ticks.end(), [](double t) { return t != std::round(t); }),
                  x_ticks.end());
  // Grid and frame first, so that the data covers the grid; then the frame again on top.
  draw_axes(c, area, ax, x_ticks, y_ticks, chart.title, chart.x_label, chart.y_label, scale);
  if (bars) {
    for (size_t s = 0; s < layers; ++s)
      for (size_t i = 0; i < n; ++i) {
        const double bottom = s ? top[s - 1][i] : 0;
        c.fill_rect(ax.px(chart.x[i] - 0.4 * spacing), ax.py(top[s][i]), ax.px(chart.x[i] + 0.4 * spacing),
                    ax.py(bottom), series_color(int(s)));
      }
  } else {
    // Each cumulative curve filled down to 0, the topmost first: in a pixel column holding
    // several samples every boundary is the column's maximum of its curve, so spikes show
    // and no layer looks thicker than it is.
    std::vector<double> xs(n), y_top(n), y_zero(n, ax.py(0));
    for (size_t i = 0; i < n; ++i) xs[i] = ax.px(chart.x[i]);
    for (size_t s = layers; s-- > 0;) {
      for (size_t i = 0; i < n; ++i) y_top[i] = ax.py(top[s][i]);
      c.fill_between(xs, y_top, y_zero, series_color(int(s)));
    }
  }
  const Rect& p = ax.plot;
  c.line({p.x + 0.5, p.y + p.height - 0.5}, {p.x + p.width - 0.5, p.y + p.height - 0.5}, kInk);
  c.line({p.x + 0.5, p.y + 0.5}, {p.x + 0.5, p.y + p.height - 0.5}, kInk);
  std::vector<std::pair<std::string, Rgb>> entries;
  for (size_t s = layers; s-- > 0;) entries.emplace_back(s < chart.names.size() ? chart.names[s] : "", series_color(int(s)));
  draw_legend(c, p.x + p.width + 3 * 4 * scale, p.y, entries, scale);
}

void draw_histogram(Canvas& c, Rect area, const Histogram& chart) {
  const int scale = chart.text_scale;
  std::vector<double> samples;
  for (double v : chart.samples)
    if (std::isfinite(v)) samples.push_back(v);
  double lo = samples.empty() ? 0 : *std::min_element(samples.begin(), samples.end());
  double hi = samples.empty() ? 1 : *std::max_element(samples.begin(), samples.end());
  if (!(hi > lo)) {
    const double pad = lo == 0 ? 0.5 : 0.05 * std::abs(lo);
    lo -= pad;
    hi += pad;
  }
  const int bins = chart.bins > 0 ? chart.bins
                                  : std::clamp(static_cast<int>(std::ceil(std::sqrt(double(samples.size())))), 5, 40);
  std::vector<int> counts(bins, 0);
  for (double v : samples) counts[std::min(bins - 1, static_cast<int>((v - lo) / (hi - lo) * bins))]++;
  double y_lo = 0, y_hi = std::max(1, *std::max_element(counts.begin(), counts.end()));
  nice_range(y_lo, y_hi, 6, true);
  y_lo = 0;
  std::vector<double> y_ticks = linear_ticks(y_lo, y_hi, 6);
  y_ticks.erase(std::remove_if(y_ticks.begin(), y_ticks.end(), [](double t) { return t != std::round(t); }),
                y_ticks.end());
  Axes ax;
  ax.plot = layout(area, scale, max_label_width(y_ticks, scale), 0);
  ax.x_lo = lo;
  ax.x_hi = hi;
  ax.y_lo = y_lo;
  ax.y_hi = y_hi;
  draw_axes(c, area, ax, fitting_ticks(lo, hi, ax.plot.width, scale), y_ticks, chart.title, chart.x_label, chart.y_label,
            scale);
  const double width = (hi - lo) / bins;
  for (int b = 0; b < bins; ++b) {
    if (!counts[b]) continue;
    // One pixel of background between neighbouring bars when they are wide enough.
    const double x0 = ax.px(lo + b * width), x1 = ax.px(lo + (b + 1) * width);
    c.fill_rect(x0, ax.py(counts[b]), x1 - (x1 - x0 >= 4 ? 1 : 0), ax.py(0), chart.color);
  }
  const Rect& p = ax.plot;
  const int th = Canvas::text_height(scale);
  for (size_t k = 0; k < chart.markers.size(); ++k) {
    const Marker& m = chart.markers[k];
    if (!(m.x >= lo && m.x <= hi)) continue;
    const double x = snap(ax.px(m.x));
    c.line({x, double(p.y)}, {x, double(p.y + p.height)}, kInk, 1, 3 * scale);
    // Labels on alternate rows, so that close markers stay readable.
    const double y = p.y + 2 * scale + (k % 2) * (th + 2 * scale);
    const bool right_half = x > p.x + 0.5 * p.width;
    const double w = Canvas::text_width(m.label, scale), left = right_half ? x - 3 * scale - w : x + 3 * scale;
    c.fill_rect(left - scale, y - scale, left + w + scale, y + th + scale, kBackground);  // readable over a bar
    c.text(left, y, m.label, kInk, scale);
  }
}

void draw_line_chart(Canvas& c, Rect area, const LineChart& chart) {
  const int scale = chart.text_scale;
  auto usable = [&](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && (!chart.log_x || x > 0) && (!chart.log_y || y > 0);
  };
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const Series& s : chart.series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], s.y[i])) {
        x_lo = std::min(x_lo, s.x[i]), x_hi = std::max(x_hi, s.x[i]);
        y_lo = std::min(y_lo, s.y[i]), y_hi = std::max(y_hi, s.y[i]);
      }
  if (!std::isfinite(x_lo)) x_lo = 1, x_hi = 10, y_lo = 1, y_hi = 10;
  if (chart.log_x) log_range(x_lo, x_hi);
  else nice_range(x_lo, x_hi, 6);
  if (chart.log_y) log_range(y_lo, y_hi);
  else nice_range(y_lo, y_hi, 6);
  const std::vector<double> x_ticks = chart.log_x ? log_ticks(x_lo, x_hi) : linear_ticks(x_lo, x_hi, 6);
  const std::vector<double> y_ticks = chart.log_y ? log_ticks(y_lo, y_hi) : linear_ticks(y_lo, y_hi, 6);
  std::vector<std::string> names;
  std::vector<std::pair<std::string, Rgb>> entries;
  for (size_t k = 0; k < chart.series.size(); ++k) {
    names.push_back(chart.series[k].name);
    entries.emplace_back(chart.series[k].name, series_color(int(k)));
  }
  Axes ax;
  const int column = chart.legend == LegendPlace::Right ? legend_width(names, scale) : 0;
  ax.plot = layout(area, scale, max_label_width(y_ticks, scale), column);
  ax.x_lo = x_lo, ax.x_hi = x_hi, ax.y_lo = y_lo, ax.y_hi = y_hi;
  ax.log_x = chart.log_x, ax.log_y = chart.log_y;
  draw_axes(c, area, ax, x_ticks, y_ticks, chart.title, chart.x_label, chart.y_label, scale);

  const double r = 3.0 * scale;  // marker half-size
  for (size_t k = 0; k < chart.series.size(); ++k) {
    const Series& s = chart.series[k];
    const Rgb color = series_color(int(k));
    std::vector<Point> points;
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], s.y[i])) points.push_back({ax.px(s.x[i]), ax.py(s.y[i])});
    if (s.lines)
      for (size_t i = 0; i + 1 < points.size(); ++i) c.line(points[i], points[i + 1], color, std::max(1, scale));
    if (s.markers)
      for (const Point& q : points) {
        if (k % 3 == 0) c.fill_rect(q.x - r, q.y - r, q.x + r, q.y + r, color);
        else if (k % 3 == 1) c.fill_polygon({{q.x, q.y - 1.2 * r}, {q.x + 1.2 * r, q.y + r}, {q.x - 1.2 * r, q.y + r}}, color);
        else c.fill_polygon({{q.x, q.y - 1.3 * r}, {q.x + 1.3 * r, q.y}, {q.x, q.y + 1.3 * r}, {q.x - 1.3 * r, q.y}}, color);
      }
  }
  const Rect& p = ax.plot;
  if (entries.empty() || chart.legend == LegendPlace::None) return;
  if (chart.legend == LegendPlace::Right) {  // in the column layout() left, as the stacked chart's
    draw_legend(c, p.x + p.width + 3 * 4 * scale, p.y, entries, scale);
    return;
  }
  // Legend in the top-right corner of the plot, on a framed white box.
  const int th = Canvas::text_height(scale), pad = 4 * scale;
  const double w = legend_width(names, scale) + 2 * pad, h = (2 * entries.size() - 1) * th + 2 * pad;
  const double x0 = p.x + p.width - pad - w, y0 = p.y + pad;
  c.fill_rect(x0, y0, x0 + w, y0 + h, kBackground);
  c.line({snap(x0), snap(y0)}, {snap(x0 + w), snap(y0)}, kInk);
  c.line({snap(x0), snap(y0 + h)}, {snap(x0 + w), snap(y0 + h)}, kInk);
  c.line({snap(x0), snap(y0)}, {snap(x0), snap(y0 + h)}, kInk);
  c.line({snap(x0 + w), snap(y0)}, {snap(x0 + w), snap(y0 + h)}, kInk);
  draw_legend(c, x0 + pad, y0 + pad, entries, scale);
}

}  // namespace sinew::plot
