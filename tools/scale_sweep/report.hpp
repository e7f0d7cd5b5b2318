#pragma once
// The scale sweep's outputs: per-stage order statistics and speedups of the measured
// sizes, the JSON file, and two charts drawn by tools/plot.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tools/scale_sweep/measure.hpp"

namespace sinew::sweep {

// "step" (the whole step), then every stage of engine/profile.hpp in order.
std::vector<std::string> stage_names();
// The stages drawn in the charts: all but "integrate" (a vector update, ~1 % of "surface").
std::vector<std::string> charted_stages();

// Per timed step of a run, ms: the step's time for "step", else the stage's.
std::vector<double> stage_samples(const ThreadRun& run, const std::string& stage);
double median_ms(const ThreadRun& run, const std::string& stage);
// Whether the stage did work in each timed step: not reported skipped (a step that solved
// no QP reports the SQP's stages skipped) and, for sqp_factorize, an SQP refactorisation
// happened (else its time is the timer's alone).
std::vector<bool> worked(const ThreadRun& run, const std::string& stage);
// The median when the stage worked in more than half the timed steps, else none.
std::optional<double> working_median_ms(const ThreadRun& run, const std::string& stage);
// Speedup of `run` over `base`: the ratio of their working medians; none without both.
std::optional<double> speedup(const ThreadRun& base, const ThreadRun& run, const std::string& stage);

// The figures to compare with (issue 7, section 5).
struct Reference {
  std::string name;
  std::vector<double> elements, step_ms;
};
Reference vegafem_reference();  // 21 ms for 500 hex, 210 ms for 2,560; one thread, no constraints
inline constexpr double kAssemblySpeedupTarget = 1.7;  // 2 threads over 1

struct RunInfo {
  std::string command, date_utc, cpu;
  int processors = 0;
  std::array<double, 3> load_start{}, load_end{};
  double wall_seconds = 0;
};

nlohmann::json size_json(const SizeResult& size);
nlohmann::json sweep_json(const std::vector<SizeResult>& sizes, const SweepOptions& options, const RunInfo& info);

// Median time per stage against element count, log-log, one panel per thread count.
void write_stage_chart(const std::vector<SizeResult>& sizes, const std::string& path);
// Speedup per stage against element count, one panel per thread count after the first
// (over the first). Nothing is written with a single thread count.
void write_speedup_chart(const std::vector<SizeResult>& sizes, const std::string& path);

}  // namespace sinew::sweep
