#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/io/stats_writer.hpp"

namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("sinew_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<sinew::FrameStats> sample_frames() {
  sinew::FrameStats a;
  a.t = 0.01;
  a.step_ms = 12.5;
  a.stages = {{"collide", 3.0}, {"solve", 8.0}, {"collide", 0.5}};
  a.rows = {{"contact", 42}};
  a.iterations = {{"cg", 17}};
  a.violation = {{"contact", 1e-6}};
  a.kinetic_energy = 0.75;
  a.skipped = {{"plasticity", "disabled in scene"}};

  sinew::FrameStats b;
  b.t = 0.02;
  b.step_ms = 11.0;
  b.stages = {{"solve", 7.0}, {"write", 1.0}};
  b.violation = {{"contact", std::numeric_limits<double>::infinity()}};
  b.kinetic_energy = std::numeric_limits<double>::quiet_NaN();
  return {a, b};
}

}  // namespace

TEST_CASE("io: write_stats_json writes every key and null for non-finite numbers") {
  const fs::path d = fresh_dir("stats_json");
  const fs::path path = d / "stats.json";
  sinew::write_stats_json(path.string(), sample_frames(), {{"frames", 2}, {"wall_s", 0.5}});
  const nlohmann::json j = nlohmann::json::parse(slurp(path));  // throws on NaN literals

  REQUIRE(j.at("frames").size() == 2);
  const auto& a = j["frames"][0];
  for (const char* key : {"t", "step_ms", "stages", "rows", "iterations", "violation", "kinetic_energy", "finite",
                          "skipped"})
    CHECK_MESSAGE(a.contains(key), key);
  CHECK(a["t"] == 0.01);
  CHECK(a["stages"]["collide"] == 3.5);  // listed twice: summed
  CHECK(a["stages"]["solve"] == 8.0);
  CHECK(a["rows"]["contact"] == 42);
  CHECK(a["iterations"]["cg"] == 17);
  CHECK(a["violation"]["contact"] == 1e-6);
  CHECK(a["kinetic_energy"] == 0.75);
  CHECK(a["finite"] == true);
  CHECK(a["skipped"]["plasticity"] == "disabled in scene");

  const auto& b = j["frames"][1];
  CHECK(b["kinetic_energy"].is_null());
  CHECK(b["violation"]["contact"].is_null());
  CHECK(b["finite"] == false);
  CHECK(b["rows"].is_object());
  CHECK(b["skipped"].is_object());

  CHECK(j.at("summary")["frames"] == 2);
  CHECK(j["summary"]["wall_s"] == 0.5);
  CHECK(std::distance(fs::directory_iterator(d), fs::directory_iterator()) == 1);
  fs::remove_all(d);
}

TEST_CASE("io: write_stats_json keeps finite false when the frame says so") {
  const fs::path d = fresh_dir("stats_flag");
  sinew::FrameStats f;
  f.finite = false;  // e.g. the solver saw a NaN that did not reach these numbers
  sinew::write_stats_json((d / "s.json").string(), {f}, nlohmann::json::object());
  const nlohmann::json j = nlohmann::json::parse(slurp(d / "s.json"));
  CHECK(j["frames"][0]["finite"] == false);
  CHECK(j["summary"].is_object());
  fs::remove_all(d);
}

TEST_CASE("io: write_stats_csv has one column per stage in first-seen order") {
  const fs::path d = fresh_dir("stats_csv");
  const fs::path path = d / "stats.csv";
  sinew::write_stats_csv(path.string(), sample_frames());
  std::istringstream in(slurp(path));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  REQUIRE(lines.size() == 3);
  CHECK(lines[0] == "t,step_ms,collide,solve,write,kinetic_energy,finite");
  CHECK(lines[1] == "0.01,12.5,3.5,8,,0.75,true");
  CHECK(lines[2] == "0.02,11,,7,1,nan,false");
  fs::remove_all(d);
}
