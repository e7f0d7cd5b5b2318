#include "tools/bench_common.hpp"

#include <ctime>
#include <fstream>
#include <thread>

namespace sinew::bench {

std::vector<double> row_totals(const std::vector<FrameStats>& samples) {
  std::vector<double> out;
  for (const FrameStats& f : samples) {
    double total = 0;
    for (const auto& [kind, n] : f.rows) total += n;
    out.push_back(total);
  }
  return out;
}

std::vector<double> iteration_counts(const std::vector<FrameStats>& samples, const std::string& solver) {
  std::vector<double> out;
  for (const FrameStats& f : samples) {
    const auto it = f.iterations.find(solver);
    out.push_back(it == f.iterations.end() ? 0.0 : it->second);
  }
  return out;
}

std::array<double, 3> load_average() {
  std::array<double, 3> load{-1, -1, -1};
  std::ifstream in("/proc/loadavg");
  in >> load[0] >> load[1] >> load[2];
  return in ? load : std::array<double, 3>{-1, -1, -1};
}

std::string cpu_model() {
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string line; std::getline(cpu, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

int processor_count() { return static_cast<int>(std::thread::hardware_concurrency()); }

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  char s[32];
  std::strftime(s, sizeof s, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return s;
}

nlohmann::json cpu_placement_json(const std::string& mode, const CpuPlacement& placement) {
  nlohmann::json probes = nlohmann::json::array();
  for (const CpuTiming& t : placement.timings) probes.push_back({{"cpu", t.cpu}, {"probe_ms", t.ms}});
  return {{"mode", mode}, {"probes", probes}, {"pinned_cpu", placement.pinned_cpu}, {"summary", placement.summary}};
}

}  // namespace sinew::bench
