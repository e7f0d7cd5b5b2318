#pragma once
// The outputs of sinew_work_precision: JSON with every point, a log-log chart per family,
// and a Markdown summary with the papers' comparisons as tables.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tools/work_precision/study.hpp"

namespace sinew::wp {

struct RunInfo {
  std::string command;   // as typed
  std::string date;      // UTC, ISO 8601
  std::string machine;   // CPU model and core count
  bool quick = false;
  int threads = 1;
  double total_seconds = 0;
};

nlohmann::json to_json(const std::vector<FamilyResult>& families, const RunInfo& info);

// Error against wall time per simulated second, log-log, one series per variant and swept
// setting: surface RMS distance on the left; the family's constraint violation (or, without
// constraints, the energy error) on the right. PNG, written whole or not at all.
void write_family_chart(const FamilyResult& family, const std::string& path);

std::string markdown_summary(const std::vector<FamilyResult>& families, const RunInfo& info);

}  // namespace sinew::wp
