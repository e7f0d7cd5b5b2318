#pragma once
// Per-frame run statistics (timings, solver sizes, constraint violation) as JSON and CSV.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace sinew {

struct FrameStats {
  double t = 0;
  double step_ms = 0;
  std::vector<std::pair<std::string, double>> stages;  // stage -> ms, in execution order
  std::map<std::string, int> rows;
  std::map<std::string, int> iterations;
  std::map<std::string, double> violation;
  double kinetic_energy = 0;
  bool finite = true;
  std::vector<std::pair<std::string, std::string>> skipped;  // stage -> reason
};

// {"frames": [{"t", "step_ms", "stages": {name: ms}, "rows", "iterations", "violation",
// "kinetic_energy", "finite", "skipped": {stage: reason}}...], "summary": summary}.
// A stage listed twice in one frame is summed. Non-finite numbers become null and make that
// frame's "finite" false. Written atomically.
void write_stats_json(const std::string& path, const std::vector<FrameStats>& frames,
                      const nlohmann::json& summary);

// One row per frame: t, step_ms, one column per stage name (first-seen order over all
// frames; empty when a frame lacks it), kinetic_energy, finite ("finite" as in the JSON).
void write_stats_csv(const std::string& path, const std::vector<FrameStats>& frames);

}  // namespace sinew
