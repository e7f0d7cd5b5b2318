#include "tools/scale_sweep/report.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <set>

#include "engine/io/stats_summary.hpp"
#include "engine/profile.hpp"
#include "tools/bench_common.hpp"
#include "tools/plot/charts.hpp"

namespace sinew::sweep {

namespace {

using nlohmann::json;

json order_statistics(const std::vector<double>& v) {
  return {{"median", quantile(v, 0.5)}, {"p95", quantile(v, 0.95)}, {"min", quantile(v, 0.0)}, {"max", quantile(v, 1.0)}};
}

// Per-kind maps of the samples (rows by kind, iterations by solver) as order statistics.
json counts_json(const ThreadRun& run, std::map<std::string, int> FrameStats::*field) {
  std::set<std::string> keys;
  for (const FrameStats& f : run.samples)
    for (const auto& [key, n] : f.*field) keys.insert(key);
  json out = json::object();
  for (const std::string& key : keys) {
    std::vector<double> v;
    for (const FrameStats& f : run.samples) v.push_back((f.*field).count(key) ? (f.*field).at(key) : 0);
    out[key] = order_statistics(v);
  }
  return out;
}

json run_json(const ThreadRun& run) {
  json stages = json::object(), samples = json::object();
  for (const std::string& stage : stage_names()) {
    const std::vector<double> v = stage_samples(run, stage);
    const std::vector<bool> w = worked(run, stage);
    stages[stage] = {{"median_ms", quantile(v, 0.5)}, {"p95_ms", quantile(v, 0.95)}, {"min_ms", quantile(v, 0.0)},
                     {"max_ms", quantile(v, 1.0)}, {"idle_steps", std::count(w.begin(), w.end(), false)}};
    const std::optional<double> m = working_median_ms(run, stage);
    stages[stage]["working_median_ms"] = m ? json(*m) : json(nullptr);
    samples[stage] = v;
  }
  return {{"threads", run.threads},
          {"finite", run.finite},
          {"state_hash", run.state_hash},
          {"stages", stages},
          {"rows", order_statistics(bench::row_totals(run.samples))},
          {"rows_by_kind", counts_json(run, &FrameStats::rows)},
          {"iterations", counts_json(run, &FrameStats::iterations)},
          {"samples_ms", samples},
          {"samples_rows", bench::row_totals(run.samples)},
          {"samples_sqp", bench::iteration_counts(run.samples, "sqp")},
          {"samples_pgs", bench::iteration_counts(run.samples, "pgs")}};
}

json speedup_json(const ThreadRun& base, const ThreadRun& run) {
  json out = json::object();
  for (const std::string& stage : stage_names()) {
    const std::optional<double> s = speedup(base, run, stage);
    // Paired: the same step (identical in every World) timed on both thread counts.
    const std::vector<double> a = stage_samples(base, stage), b = stage_samples(run, stage);
    const std::vector<bool> wa = worked(base, stage), wb = worked(run, stage);
    std::vector<double> ratios;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
      if (wa[i] && wb[i] && a[i] > 0 && b[i] > 0) ratios.push_back(a[i] / b[i]);
    out[stage] = {{"of_medians", s ? json(*s) : json(nullptr)},
                  {"paired_median", ratios.empty() ? json(nullptr) : json(quantile(ratios, 0.5))}};
  }
  return out;
}

// x = elements, y = value(size) for every size where it has one.
plot::Series series_over_sizes(const std::string& name, const std::vector<SizeResult>& sizes,
                               const std::function<std::optional<double>(const SizeResult&)>& value) {
  plot::Series s{name, {}, {}};
  for (const SizeResult& size : sizes)
    if (const std::optional<double> y = value(size)) {
      s.x.push_back(size.elements);
      s.y.push_back(*y);
    }
  return s;
}

plot::Series reference_series(const Reference& ref) {
  plot::Series s{ref.name, ref.elements, ref.step_ms};
  s.lines = false;
  return s;
}

// Panels side by side, the first wider: it carries the legend column for all.
std::vector<plot::Rect> panels(int count, int width, int height, int legend_column) {
  std::vector<plot::Rect> out;
  const int each = (width - legend_column) / count;
  for (int i = 0, x = 0; i < count; ++i) {
    const int w = each + (i == 0 ? legend_column : 0);
    out.push_back({x, 0, w, height});
    x += w;
  }
  return out;
}

}  // namespace

std::vector<std::string> stage_names() {
  std::vector<std::string> out{"step"};
  for (int s = 0; s < kStageCount; ++s) out.push_back(stage_name(static_cast<Stage>(s)));
  return out;
}

std::vector<std::string> charted_stages() {
  std::vector<std::string> out = stage_names();
  out.erase(std::remove(out.begin(), out.end(), "integrate"), out.end());
  return out;
}

std::vector<double> stage_samples(const ThreadRun& run, const std::string& stage) {
  std::vector<double> out;
  for (const FrameStats& f : run.samples) {
    double ms = stage == "step" ? f.step_ms : 0;
    for (const auto& [name, t] : f.stages)
      if (name == stage) ms += t;
    out.push_back(ms);
  }
  return out;
}

double median_ms(const ThreadRun& run, const std::string& stage) { return quantile(stage_samples(run, stage), 0.5); }

std::vector<bool> worked(const ThreadRun& run, const std::string& stage) {
  std::vector<bool> out;
  for (const FrameStats& f : run.samples) {
    bool work = std::none_of(f.skipped.begin(), f.skipped.end(), [&](const auto& s) { return s.first == stage; });
    if (stage == "sqp_factorize") work = work && f.iterations.count("sqp_refactorisations");
    out.push_back(work);
  }
  return out;
}

std::optional<double> working_median_ms(const ThreadRun& run, const std::string& stage) {
  const std::vector<bool> w = worked(run, stage);
  if (2 * std::count(w.begin(), w.end(), true) <= static_cast<long>(w.size())) return std::nullopt;
  return median_ms(run, stage);
}

std::optional<double> speedup(const ThreadRun& base, const ThreadRun& run, const std::string& stage) {
  const std::optional<double> a = working_median_ms(base, stage), b = working_median_ms(run, stage);
  if (!a || !b || !(*a > 0 && *b > 0)) return std::nullopt;
  return *a / *b;
}

Reference vegafem_reference() { return {"VegaFEM step, 1 thread, no constraints (issue 7)", {500, 2560}, {21, 210}}; }

json size_json(const SizeResult& size) {
  json runs = json::array(), speedups = json::object();
  for (const ThreadRun& run : size.runs) runs.push_back(run_json(run));
  for (size_t i = 1; i < size.runs.size(); ++i)
    speedups[std::to_string(size.runs[i].threads)] = speedup_json(size.runs[0], size.runs[i]);
  return {{"target", size.target},
          {"lattice", {size.dims.nx, size.dims.ny, size.dims.nz}},
          {"cell_size", size.dims.cell_size},
          {"elements", size.elements},
          {"nodes", size.nodes},
          {"dofs", size.dofs},
          {"surface_vertices", size.surface_vertices},
          {"build_seconds", size.build_seconds},
          {"warmup_steps", size.warmup},
          {"timed_steps", size.steps},
          {"state_hashes_equal", size.hashes_equal()},
          {"scene", json::parse(size.scene_text)},
          {"runs", runs},
          {"speedup_over_" + std::to_string(size.runs.empty() ? 0 : size.runs[0].threads) + "_thread", speedups}};
}

json sweep_json(const std::vector<SizeResult>& sizes, const SweepOptions& options, const RunInfo& info) {
  const RestingBlock& block = options.block;
  json out = {
      {"tool", "sinew_scale_sweep"},
      {"command", info.command},
      {"date_utc", info.date_utc},
      {"wall_seconds", info.wall_seconds},
      {"machine",
       {{"cpu", info.cpu}, {"nproc", info.processors}, {"load_average_start", info.load_start},
        {"load_average_end", info.load_end}}},
      {"options",
       {{"sizes", options.sizes}, {"steps", options.steps}, {"warmup", options.warmup}, {"budget_s", options.budget},
        {"threads_list", options.threads}, {"quick", options.quick}}},
      {"scene",
       {{"what", "a 1 m x 0.5 m x 0.5 m block of 2k x k x k hex (cell 0.5 m / k) resting on a ground plane with "
                 "friction from t = 0, sagging under gravity; corotational; energy limit per element = density x "
                 "cell volume; the same 0.1 m embedded surface at every size; h = 1/60 s; bodies never sleep; "
                 "each size's scene text is under sizes[i].scene"},
        {"height", block.height}, {"E", block.E}, {"nu", block.nu}, {"rho", block.rho},
        {"stiffness_damping", block.stiffness_damping}, {"energy_density_limit", block.energy_density_limit},
        {"surface_resolution", block.surface_resolution}, {"contact_margin", block.contact_margin},
        {"friction", block.friction}, {"h", block.h}}},
      {"method",
       "one World per thread count (tbb::global_control), stepped in turn, one step each, so that load changes hit "
       "all alike; warm-up steps untimed; per-stage wall times from the engine's StepProfile; medians over the timed "
       "steps; a stage is idle in a step when the engine reports it skipped (sqp_factorize: when no SQP "
       "refactorisation happened); working_median_ms and the speedups are null for a stage idle in half the steps "
       "or more; speedup = median at the first thread count / median at the other (of_medians), and the median of "
       "the per-step ratios, the same step being timed at both (paired_median)"},
      {"targets",
       {{"assembly_speedup_2_threads", kAssemblySpeedupTarget},
        {"vegafem_step_ms", {{{"elements", 500}, {"ms", 21}}, {{"elements", 2560}, {"ms", 210}}}}}},
      {"stages", stage_names()},
      {"sizes", json::array()}};
  for (const SizeResult& size : sizes) out["sizes"].push_back(size_json(size));
  return out;
}

void write_stage_chart(const std::vector<SizeResult>& sizes, const std::string& path) {
  if (sizes.empty() || sizes[0].runs.empty()) return;
  const int count = static_cast<int>(sizes[0].runs.size());
  const int width = 900 * count + 420, height = 900;
  plot::Canvas canvas(width, height);
  const std::vector<plot::Rect> areas = panels(count, width, height, 420);
  for (int r = 0; r < count; ++r) {
    plot::LineChart chart;
    const int threads = sizes[0].runs[r].threads;
    chart.title = "median time per step, " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
    chart.x_label = "hexahedra";
    chart.y_label = "ms";
    for (const std::string& stage : charted_stages())
      chart.series.push_back(
          series_over_sizes(stage, sizes, [&](const SizeResult& s) { return working_median_ms(s.runs[r], stage); }));
    chart.series.push_back(reference_series(vegafem_reference()));
    chart.legend = r == 0 ? plot::LegendPlace::Right : plot::LegendPlace::None;
    plot::draw_line_chart(canvas, areas[r], chart);
  }
  plot::write_png(path, canvas);
}

void write_speedup_chart(const std::vector<SizeResult>& sizes, const std::string& path) {
  if (sizes.empty() || sizes[0].runs.size() < 2) return;
  const int count = static_cast<int>(sizes[0].runs.size()) - 1;
  const int width = 900 * count + 420, height = 900;
  plot::Canvas canvas(width, height);
  const std::vector<plot::Rect> areas = panels(count, width, height, 420);
  const int base = sizes[0].runs[0].threads;
  for (int r = 1; r <= count; ++r) {
    plot::LineChart chart;
    chart.title = "speedup of " + std::to_string(sizes[0].runs[r].threads) + " threads over " + std::to_string(base);
    chart.x_label = "hexahedra";
    chart.y_label = "median time ratio";
    chart.log_y = false;
    for (const std::string& stage : charted_stages())
      chart.series.push_back(series_over_sizes(
          stage, sizes, [&](const SizeResult& s) { return speedup(s.runs[0], s.runs[r], stage); }));
    const double lo = sizes.front().elements, hi = sizes.back().elements;
    chart.series.push_back({"1.7: the assembly target", {lo, hi}, {kAssemblySpeedupTarget, kAssemblySpeedupTarget}});
    chart.series.back().markers = false;
    chart.legend = r == 1 ? plot::LegendPlace::Right : plot::LegendPlace::None;
    plot::draw_line_chart(canvas, areas[r - 1], chart);
  }
  plot::write_png(path, canvas);
}

}  // namespace sinew::sweep
