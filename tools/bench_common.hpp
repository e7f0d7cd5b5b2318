#pragma once
// What the benchmark programs share (sinew_bench, sinew_scale_sweep): counts read from the
// per-step stats of timed steps, and facts about the machine a run was made on.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/cpu_placement.hpp"
#include "engine/io/stats_writer.hpp"

namespace sinew::bench {

// Active constraint rows of each sample, all kinds together.
std::vector<double> row_totals(const std::vector<FrameStats>& samples);
// One solver's (or event's) count per sample ("sqp", "pgs", ...); 0 where absent.
std::vector<double> iteration_counts(const std::vector<FrameStats>& samples, const std::string& solver);

// The 1, 5 and 15 minute load averages from /proc/loadavg (-1 each when unreadable).
std::array<double, 3> load_average();
// "model name" of /proc/cpuinfo, or "unknown CPU".
std::string cpu_model();
// Logical processors (std::thread::hardware_concurrency()).
int processor_count();
// "YYYY-MM-DD HH:MM UTC".
std::string utc_now();
// A run's CPU placement for its JSON: the mode, the probe's time per CPU, the CPU the main
// thread was pinned to (-1: none) and the summary line.
nlohmann::json cpu_placement_json(const std::string& mode, const CpuPlacement& placement);

}  // namespace sinew::bench
