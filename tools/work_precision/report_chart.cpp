#include <functional>
#include <map>

#include "tools/plot/charts.hpp"
#include "tools/work_precision/report.hpp"

namespace sinew::wp {

namespace {

// One series per (variant, sweep), points in the sweep's order; failed runs left out.
std::vector<plot::Series> series_of(const FamilyResult& f, const std::function<double(const Point&)>& error) {
  std::vector<plot::Series> out;
  std::map<std::string, size_t> index;
  for (const Point& p : f.points) {
    const std::string name = p.variant + ": " + p.sweep;
    auto [it, added] = index.emplace(name, out.size());
    if (added) out.push_back({name, {}, {}});
    if (!p.run.finite) continue;
    out[it->second].x.push_back(p.seconds_per_simulated_second);
    out[it->second].y.push_back(error(p));
  }
  return out;
}

}  // namespace

void write_family_chart(const FamilyResult& f, const std::string& path) {
  // The left chart is wider: it carries the legend column for both.
  const int width = 2000, height = 820, left = 1100;
  plot::Canvas canvas(width, height);
  plot::LineChart rms;
  rms.title = f.name + ": surface RMS distance to the reference";
  rms.x_label = "wall time per simulated second (s)";
  rms.y_label = "RMS distance (m)";
  rms.series = series_of(f, [](const Point& p) { return p.errors.rms_distance; });
  rms.legend = plot::LegendPlace::Right;
  plot::draw_line_chart(canvas, {0, 0, left, height}, rms);

  plot::LineChart second;  // the same series and colours: the left chart's legend serves both
  second.x_label = rms.x_label;
  second.legend = plot::LegendPlace::None;
  if (!f.violation_kind.empty()) {
    const std::string& kind = f.violation_kind;
    second.title = f.name + ": worst " + kind + " violation over the run";
    second.y_label = kind == "penetration" ? "penetration (m)" : kind == "energy" ? "Ue/Umax - 1" : "strain past the limit";
    second.series = series_of(f, [&](const Point& p) {
      const auto it = p.run.worst_violation.find(kind);
      return it == p.run.worst_violation.end() ? 0.0 : it->second;
    });
  } else {
    second.title = f.name + ": energy error (relative to the reference's change)";
    second.y_label = "max |E - E_ref| / max |E_ref - E_ref(0)|";
    second.series = series_of(f, [](const Point& p) { return p.errors.energy_error; });
  }
  plot::draw_line_chart(canvas, {left, 0, width - left, height}, second);
  plot::write_png(path, canvas);
}

}  // namespace sinew::wp
