// `sinew profile`: where the time of a run went, per stage, from its stats file.
#include "tools/cli_profile.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/profile.hpp"
#include "tools/cli_options.hpp"
#include "tools/plot/charts.hpp"

namespace sinew::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr plot::Rgb kHistogramColor{70, 90, 125};  // not a stage colour

Options profile_options() {
  return Options(
      "sinew profile STATS [options]",
      "Reads STATS, the JSON that `sinew run SCENE --stats STATS` writes, and prints per stage the\n"
      "median, p95, p99, max and mean time per frame (each frame is the sum of its steps), the\n"
      "stage's share of the total and how many frames skipped it; then the same statistics of\n"
      "the counts per frame (constraint rows by kind, solver iterations). Percentiles are\n"
      "nearest-rank: the value of rank ceil(p/100 * n) among the n frames sorted ascending.\n"
      "Frames whose value is null (a non-finite run) are left out of that row.",
      {{"--plot", "OUT.png", "also draw a PNG chart: per-stage time per frame over the run (stacked),\n"
                             "                          and a histogram of the frame time with its median, p95, p99"},
       {"--csv", "OUT.csv", "also write one row per frame: frame, t, step_ms, each stage's ms,\n"
                            "                          untimed_ms, each count, finite"},
       {"--size", "WxH", "size of the --plot picture in pixels (default 1200x900)"}},
      1);
}

// One run's stats file, per frame. Times in ms, NaN where the file holds null.
struct RunProfile {
  std::string scene;
  int steps_per_frame = 0;  // 0: unknown (no summary)
  double h = 0;
  std::vector<double> t, step_ms;
  std::vector<std::string> stages;             // pipeline order (engine/profile.hpp), then others
  std::vector<std::vector<double>> stage_ms;   // [stage][frame]; 0 when a frame lacks the stage
  std::vector<int> frames_skipped;             // per stage
  std::vector<double> untimed_ms;              // step_ms minus the sum of the stages
  std::vector<std::string> counts;             // "rows.KIND", "iterations.SOLVER"
  std::vector<std::vector<double>> count_values;  // [count][frame]; 0 when a frame lacks it
  std::vector<bool> finite;
};

// Reads the stats JSON, checking every field it uses; errors name the file and JSON path.
class StatsReader {
 public:
  explicit StatsReader(std::string file) : m_file(std::move(file)) {}

  RunProfile read() {
    std::ifstream in(m_file, std::ios::binary);
    if (!in) {
      std::error_code ec;
      throw InputError("cannot read stats file '" + m_file + "': " +
                       (std::filesystem::exists(m_file, ec) ? "permission denied or not a file" : "no such file"));
    }
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
      std::string what = e.what();
      if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
      throw InputError("stats file '" + m_file + "' is not JSON: " + what);
    }
    expect(doc, "", nlohmann::json::value_t::object, "an object (the output of `sinew run --stats`)");
    RunProfile run;
    read_summary(doc, run);
    if (!doc.contains("frames")) fail("/frames", "missing (expected the array of frames)");
    const nlohmann::json& frames = doc["frames"];
    expect(frames, "/frames", nlohmann::json::value_t::array, "an array of frames");
    if (frames.empty()) fail("/frames", "empty: the run wrote no frame, nothing to profile");
    for (size_t f = 0; f < frames.size(); ++f) read_frame(frames[f], "/frames/" + std::to_string(f), f, run);
    finish(run);
    return run;
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InputError("stats file '" + m_file + "', at " + (path.empty() ? "/" : path) + ": " + what);
  }

  void expect(const nlohmann::json& j, const std::string& path, nlohmann::json::value_t type,
              const std::string& expected) const {
    const bool ok = type == nlohmann::json::value_t::number_float ? j.is_number() : j.type() == type;
    if (!ok) fail(path, std::string("expected ") + expected + ", got " + j.type_name());
  }

  // A number, or null for a value that was not finite (the writer's convention): NaN.
  double time_or_null(const nlohmann::json& j, const std::string& path) const {
    if (j.is_null()) return kNaN;
    if (!j.is_number()) fail(path, std::string("expected a number of milliseconds or null, got ") + j.type_name());
    return j.get<double>();
  }

  void read_summary(const nlohmann::json& doc, RunProfile& run) const {
    if (!doc.contains("summary")) return;  // optional: only the header uses it
    const nlohmann::json& s = doc["summary"];
    expect(s, "/summary", nlohmann::json::value_t::object, "an object");
    if (s.contains("scene")) {
      expect(s["scene"], "/summary/scene", nlohmann::json::value_t::string, "a string");
      run.scene = s["scene"].get<std::string>();
    }
    if (s.contains("steps_per_frame")) {
      if (!s["steps_per_frame"].is_number_integer() || s["steps_per_frame"].get<long>() < 1)
        fail("/summary/steps_per_frame", "expected an integer >= 1");
      run.steps_per_frame = s["steps_per_frame"].get<int>();
    }
    if (s.contains("h")) {
      expect(s["h"], "/summary/h", nlohmann::json::value_t::number_float, "a number (seconds)");
      run.h = s["h"].get<double>();
    }
  }

  static size_t index_of(std::vector<std::string>& names, std::vector<std::vector<double>>& values,
                         const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return it - names.begin();
    names.push_back(name);
    values.emplace_back();
    return names.size() - 1;
  }

  void read_frame(const nlohmann::json& j, const std::string& path, size_t f, RunProfile& run) {
    expect(j, path, nlohmann::json::value_t::object, "a frame object");
    run.t.push_back(kNaN);
    if (j.contains("t")) run.t.back() = time_or_null(j["t"], path + "/t");
    if (!j.contains("step_ms")) fail(path + "/step_ms", "missing (expected the frame's time in ms)");
    run.step_ms.push_back(time_or_null(j["step_ms"], path + "/step_ms"));
    if (!j.contains("stages")) fail(path + "/stages", "missing (expected an object: stage -> ms)");
    expect(j["stages"], path + "/stages", nlohmann::json::value_t::object, "an object: stage -> ms");
    for (const auto& [name, value] : j["stages"].items()) {
      const size_t s = index_of(run.stages, run.stage_ms, name);
      run.stage_ms[s].resize(f, 0.0);  // frames before the stage first appeared
      run.stage_ms[s].push_back(time_or_null(value, path + "/stages/" + name));
    }
    for (const char* group : {"rows", "iterations"}) {
      if (!j.contains(group)) continue;
      const std::string group_path = path + "/" + group;
      expect(j[group], group_path, nlohmann::json::value_t::object, "an object: name -> count");
      for (const auto& [name, value] : j[group].items()) {
        if (!value.is_number()) fail(group_path + "/" + name, std::string("expected a count, got ") + value.type_name());
        const size_t c = index_of(run.counts, run.count_values, std::string(group) + "." + name);
        run.count_values[c].resize(f, 0.0);
        run.count_values[c].push_back(value.get<double>());
      }
    }
    run.finite.push_back(true);
    if (j.contains("finite")) {
      expect(j["finite"], path + "/finite", nlohmann::json::value_t::boolean, "true or false");
      run.finite.back() = j["finite"].get<bool>();
    }
    if (j.contains("skipped")) {
      expect(j["skipped"], path + "/skipped", nlohmann::json::value_t::object, "an object: stage -> reason");
      for (const auto& item : j["skipped"].items()) m_skipped[item.key()]++;
    }
  }

  // Pads the per-frame rows, puts the stages in pipeline order, derives the untimed time.
  void finish(RunProfile& run) {
    const size_t n = run.step_ms.size();
    for (auto& v : run.stage_ms) v.resize(n, 0.0);
    for (auto& v : run.count_values) v.resize(n, 0.0);
    auto rank = [](const std::string& name) {
      for (int s = 0; s < kStageCount; ++s)
        if (name == stage_name(static_cast<Stage>(s))) return s;
      return kStageCount;
    };
    std::vector<size_t> order(run.stages.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return rank(run.stages[a]) < rank(run.stages[b]); });
    std::vector<std::string> stages;
    std::vector<std::vector<double>> stage_ms;
    for (size_t i : order) {
      stages.push_back(std::move(run.stages[i]));
      stage_ms.push_back(std::move(run.stage_ms[i]));
    }
    run.stages = std::move(stages);
    run.stage_ms = std::move(stage_ms);
    for (const std::string& s : run.stages) run.frames_skipped.push_back(m_skipped.count(s) ? m_skipped[s] : 0);
    run.untimed_ms.assign(n, 0.0);
    for (size_t f = 0; f < n; ++f) {
      double sum = 0;
      for (const auto& v : run.stage_ms) sum += v[f];
      // Below 0 only by rounding of the written numbers.
      run.untimed_ms[f] = std::isfinite(run.step_ms[f] - sum) ? std::max(0.0, run.step_ms[f] - sum) : kNaN;
    }
  }

  std::string m_file;
  std::map<std::string, int> m_skipped;
};

struct RowStats {
  int samples = 0;
  double median = 0, p95 = 0, p99 = 0, max = 0, mean = 0, total = 0;
};

RowStats row_stats(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  RowStats r;
  r.samples = static_cast<int>(finite.size());
  if (finite.empty()) return r;
  // Nearest rank (engine/io/stats_summary.hpp), as `sinew run`'s own summary.
  r.median = quantile(finite, 0.5);
  r.p95 = quantile(finite, 0.95);
  r.p99 = quantile(finite, 0.99);
  r.max = *std::max_element(finite.begin(), finite.end());
  for (double v : finite) r.total += v;
  r.mean = r.total / finite.size();
  return r;
}

std::string steps_text(int n) { return std::to_string(n) + (n == 1 ? " step" : " steps"); }

std::string format(const char* pattern, double v) {
  char s[64];
  std::snprintf(s, sizeof s, pattern, v);
  return s;
}

// Columns right-aligned to their widest cell, the first left-aligned.
std::string aligned(const std::vector<std::vector<std::string>>& rows) {
  std::vector<size_t> width;
  for (const auto& row : rows)
    for (size_t c = 0; c < row.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], row[c].size());
    }
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (size_t c = 0; c < row.size(); ++c) {
      const std::string pad(width[c] - row[c].size(), ' ');
      line += c == 0 ? row[c] + pad : "  " + pad + row[c];
    }
    line.erase(line.find_last_not_of(' ') + 1);
    out += line + "\n";
  }
  return out;
}

std::string table(const std::string& file, const RunProfile& run) {
  const size_t n = run.step_ms.size();
  const long not_finite = std::count(run.finite.begin(), run.finite.end(), false);
  std::ostringstream out;
  out << "stats: " << file << "\n";
  out << "scene '" << (run.scene.empty() ? "?" : run.scene) << "': " << n << " frames";
  if (run.steps_per_frame > 0) out << " of " << steps_text(run.steps_per_frame);
  if (run.h > 0) out << " (h = " << run.h << " s)";
  out << ", " << not_finite << " not finite\n";
  out << "times: ms per frame (the sum over the frame's "
      << (run.steps_per_frame > 0 ? steps_text(run.steps_per_frame) : "steps") << ")";
  if (run.steps_per_frame > 1) out << "; per step, divide by " << run.steps_per_frame;
  out << "\npercentiles: nearest rank over the frames (value of rank ceil(p n) in ascending order)\n\n";

  const RowStats step = row_stats(run.step_ms);
  std::vector<std::vector<std::string>> rows = {
      {"stage", "median", "p95", "p99", "max", "mean", "share", "skipped"}};
  auto time_row = [&](const std::string& name, const std::vector<double>& v, const std::string& skipped) {
    const RowStats r = row_stats(v);
    if (r.samples == 0) return rows.push_back({name, "-", "-", "-", "-", "-", "-", skipped});
    rows.push_back({name, format("%.3f", r.median), format("%.3f", r.p95), format("%.3f", r.p99),
                    format("%.3f", r.max), format("%.3f", r.mean),
                    step.total > 0 ? format("%.1f%%", 100 * r.total / step.total) : "-", skipped});
  };
  time_row("step (frame)", run.step_ms, "");
  for (size_t s = 0; s < run.stages.size(); ++s)
    time_row("  " + run.stages[s], run.stage_ms[s], std::to_string(run.frames_skipped[s]));
  time_row("  untimed", run.untimed_ms, "");
  out << aligned(rows);
  out << "(share: of the sum of step times; skipped: frames in which the stage did no work;\n"
         " untimed: step time outside the stages)\n";

  if (!run.counts.empty()) {
    out << "\ncounts per frame: rows = the most active rows of a step, iterations = summed over the steps\n\n";
    std::vector<std::vector<std::string>> count_rows = {{"count", "median", "p95", "p99", "max", "mean"}};
    for (size_t c = 0; c < run.counts.size(); ++c) {
      const RowStats r = row_stats(run.count_values[c]);
      count_rows.push_back({run.counts[c], format("%g", r.median), format("%g", r.p95), format("%g", r.p99),
                            format("%g", r.max), format("%.1f", r.mean)});
    }
    out << aligned(count_rows);
  }
  return out.str();
}

void put(std::ostream& out, double v) {
  if (!std::isfinite(v)) return;  // empty field
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.write(buf, r.ptr - buf);
}

std::string csv(const RunProfile& run) {
  std::ostringstream out;
  out << "frame,t,step_ms";
  for (const std::string& s : run.stages) out << ',' << s << "_ms";
  out << ",untimed_ms";
  for (const std::string& c : run.counts) out << ',' << c;
  out << ",finite\n";
  for (size_t f = 0; f < run.step_ms.size(); ++f) {
    out << f + 1 << ',';
    put(out, run.t[f]);
    out << ',';
    put(out, run.step_ms[f]);
    for (const auto& v : run.stage_ms) out << ',', put(out, v[f]);
    out << ',';
    put(out, run.untimed_ms[f]);
    for (const auto& v : run.count_values) out << ',', put(out, v[f]);
    out << ',' << (run.finite[f] ? "true" : "false") << '\n';
  }
  return out.str();
}

plot::Canvas chart(const RunProfile& run, int width, int height) {
  plot::Canvas canvas(width, height, plot::kBackground);
  const int scale = std::max(1, std::min(width / 560, height / 420));
  const size_t n = run.step_ms.size();
  const std::string steps = run.steps_per_frame > 0 ? steps_text(run.steps_per_frame) : "steps";

  plot::StackedChart stacked;
  stacked.title = "'" + run.scene + "': time per frame by stage (" + std::to_string(n) + " frames of " + steps + ")";
  stacked.x_label = "frame";
  stacked.y_label = "ms per frame";
  stacked.text_scale = scale;
  for (size_t f = 0; f < n; ++f) stacked.x.push_back(double(f + 1));
  // Stages that never took time would only crowd the legend.
  auto add = [&](const std::string& name, const std::vector<double>& v) {
    if (row_stats(v).max > 0) stacked.names.push_back(name), stacked.values.push_back(v);
  };
  for (size_t s = 0; s < run.stages.size(); ++s) add(run.stages[s], run.stage_ms[s]);
  add("untimed", run.untimed_ms);
  const int split = static_cast<int>(0.6 * height);
  plot::draw_stacked(canvas, {0, 0, width, split}, stacked);

  const RowStats step = row_stats(run.step_ms);
  plot::Histogram histogram;
  histogram.title = "distribution of the frame time";
  histogram.x_label = "ms per frame (" + steps + ")";
  histogram.y_label = "frames";
  histogram.samples = run.step_ms;
  histogram.color = kHistogramColor;
  histogram.markers = {{"median " + format("%.3g", step.median), step.median},
                       {"p95 " + format("%.3g", step.p95), step.p95},
                       {"p99 " + format("%.3g", step.p99), step.p99}};
  histogram.text_scale = scale;
  plot::draw_histogram(canvas, {0, split, width, height - split}, histogram);
  return canvas;
}

void parse_size(const std::string& text, int& width, int& height) {
  const auto x = text.find('x');
  auto number = [&](const std::string& s, int& v) {
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && p == s.data() + s.size() && v >= 200 && v <= 8192;
  };
  if (x == std::string::npos || !number(text.substr(0, x), width) || !number(text.substr(x + 1), height))
    throw UsageError("option --size expects WxH with W and H from 200 to 8192, got '" + text + "'");
}

// Checked for every output before any is written, so that a bad second path leaves no first file.
void check_output_folder(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw InputError("cannot write '" + path + "': no folder '" + folder.string() + "'");
}

// Output problems (a missing folder, no permission) are the user's to fix: exit code 2.
void write_output(const std::string& path, const std::string& bytes) {
  try {
    write_file_atomically(path, [&](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

}  // namespace

int profile_command(int argc, char** argv) {
  Options opts = profile_options();
  if (!opts.parse(argc, argv)) return 0;
  int width = 1200, height = 900;
  if (opts.has("--size")) parse_size(opts.get("--size"), width, height);
  const std::string file = opts.positional()[0];
  const RunProfile run = StatsReader(file).read();
  const std::string text = table(file, run);
  // Everything is computed before anything is written, so that a failure leaves no output.
  const std::string csv_text = opts.has("--csv") ? csv(run) : "";
  const std::string png = opts.has("--plot") ? plot::encode_png(chart(run, width, height)) : "";
  for (const char* option : {"--csv", "--plot"})
    if (opts.has(option)) check_output_folder(opts.get(option));
  if (opts.has("--csv")) write_output(opts.get("--csv"), csv_text);
  if (opts.has("--plot")) write_output(opts.get("--plot"), png);
  std::fputs(text.c_str(), stdout);
  if (opts.has("--csv")) std::printf("\nwrote %s\n", opts.get("--csv").c_str());
  if (opts.has("--plot")) std::printf("%swrote %s (%dx%d)\n", opts.has("--csv") ? "" : "\n", opts.get("--plot").c_str(), width, height);
  return 0;
}

}  // namespace sinew::cli
