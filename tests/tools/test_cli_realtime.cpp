// `sinew run --realtime / --budget`: the run reports its budget and the frames over it, and
// the stats summary records them (what the counts are depends on the machine: not asserted).
#include <doctest/doctest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/cli_runner.hpp"

using sinew::test::run_sinew;
using sinew::test::TempDir;

TEST_CASE("sinew run --realtime paces frames and reports the budget") {
  TempDir dir("realtime");
  const std::string scene = std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_sphere_150kPa.json";
  const std::string stats = (dir.path / "stats.json").string();
  const auto r = run_sinew("run " + scene + " --frames 30 --realtime --stats " + stats);
  INFO(r.output);
  REQUIRE(r.code == 0);
  CHECK(r.output.find("budget 16.7 ms per frame (paced to wall time): ") != std::string::npos);
  CHECK(r.output.find(" of 30 frames over budget") != std::string::npos);
  std::ifstream in(stats);
  const nlohmann::json j = nlohmann::json::parse(in);
  CHECK(j["summary"]["budget_ms"].get<double>() == doctest::Approx(1000.0 / 60));
  CHECK(j["summary"]["paced"].get<bool>());
  CHECK(j["summary"]["over_budget_frames"].get<int>() >= 0);
  // Paced: 30 frames of 1/60 s cannot take less than the 29 periods between their starts.
  CHECK(j["summary"]["wall_s"].get<double>() >= 29.0 / 60);
}

TEST_CASE("sinew run --budget rejects a non-positive budget") {
  const std::string scene = std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_sphere_150kPa.json";
  const auto r = run_sinew("run " + scene + " --budget 0");
  INFO(r.output);
  CHECK(r.code == 2);
  CHECK(r.output.find("--budget") != std::string::npos);
}
