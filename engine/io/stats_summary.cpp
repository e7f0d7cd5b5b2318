#include "engine/io/stats_summary.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {

double quantile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * samples.size()));
  return samples[std::min(samples.size() - 1, rank == 0 ? 0 : rank - 1)];
}

namespace {
StageSummary summarize(const std::string& name, const std::vector<double>& samples) {
  StageSummary s;
  s.name = name;
  s.median = quantile(samples, 0.5);
  s.p95 = quantile(samples, 0.95);
  s.p99 = quantile(samples, 0.99);
  s.max = samples.empty() ? 0 : *std::max_element(samples.begin(), samples.end());
  for (double v : samples) s.total += v;
  return s;
}
}  // namespace

std::vector<StageSummary> summarize_stages(const std::vector<FrameStats>& frames) {
  std::vector<std::string> names;
  for (const FrameStats& f : frames)
    for (const auto& [name, ms] : f.stages)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);

  std::vector<double> steps;
  for (const FrameStats& f : frames) steps.push_back(f.step_ms);
  std::vector<StageSummary> out{summarize("step", steps)};
  for (const std::string& name : names) {
    std::vector<double> samples;
    int skipped = 0;
    for (const FrameStats& f : frames) {
      double ms = 0;
      for (const auto& [n, v] : f.stages)
        if (n == name) ms = v;
      samples.push_back(ms);
      for (const auto& [n, reason] : f.skipped)
        if (n == name) ++skipped;
    }
    out.push_back(summarize(name, samples));
    out.back().frames_skipped = skipped;
  }
  return out;
}

}  // namespace sinew
