// `sinew profile` as a user meets it: the statistics of a known stats file, the chart and
// CSV it writes, errors for bad input (exit code 2, no output file), and a real run end to end.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "render/image.hpp"
#include "tests/support/cli_runner.hpp"
#include "tools/plot/charts.hpp"

namespace fs = std::filesystem;
using sinew::test::run_sinew;
using sinew::test::TempDir;

namespace {

// 20 frames whose step times are 1..20 ms in a scrambled order (frame f: (7 f mod 20) + 1);
// "assemble" takes a quarter of each step, "solve" a half, so a quarter is untimed.
// pgs iterations are the same permutation; contact rows are 4 in every frame.
// Nearest rank over n = 20 (rank ceil(p n)): median = 10th value, p95 = 19th, p99 = 20th.
std::string synthetic_stats(int frames = 20) {
  std::ostringstream s;
  s << R"({"frames": [)";
  for (int f = 0; f < frames; ++f) {
    const int v = (7 * f) % 20 + 1;
    s << (f ? "," : "") << R"({"t": )" << 0.01 * (f + 1) << R"(, "step_ms": )" << v
      << R"(, "stages": {"solve": )" << 0.5 * v << R"(, "assemble": )" << 0.25 * v
      << R"(}, "rows": {"contact": 4}, "iterations": {"pgs": )" << v
      << R"(}, "finite": true, "skipped": {}})";
  }
  s << R"(], "summary": {"scene": "synthetic", "steps_per_frame": 10, "h": 0.001}})";
  return s.str();
}

// The whitespace-separated fields of the first output line that starts with `name`.
std::vector<std::string> row(const std::string& output, const std::string& name) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    const auto start = line.find_first_not_of(' ');
    if (start == std::string::npos || line.compare(start, name.size(), name) != 0) continue;
    std::istringstream fields(line.substr(start + name.size()));
    std::vector<std::string> out;
    for (std::string f; fields >> f;) out.push_back(f);
    return out;
  }
  return {};
}

long count_color(const sinew::Image& image, sinew::plot::Rgb c) {
  long n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* p = image.pixel(x, y);
      n += p[0] == c.r && p[1] == c.g && p[2] == c.b;
    }
  return n;
}

// Files in the folder other than `keep`.
int other_files(const fs::path& dir, const std::string& keep) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename() != keep;
  return n;
}

}  // namespace

TEST_CASE("sinew profile: per-stage nearest-rank percentiles of a known stats file") {
  TempDir dir("profile_table");
  const std::string stats = dir.write("stats.json", synthetic_stats());
  const auto r = run_sinew("profile " + stats);
  INFO(r.output);
  REQUIRE(r.code == 0);
  CHECK(r.output.find("20 frames of 10 steps") != std::string::npos);
  CHECK(r.output.find("ms per frame") != std::string::npos);
  // median, p95, p99, max, mean, share
  CHECK(row(r.output, "step (frame)") ==
        std::vector<std::string>{"10.000", "19.000", "20.000", "20.000", "10.500", "100.0%"});
  CHECK(row(r.output, "assemble") ==
        std::vector<std::string>{"2.500", "4.750", "5.000", "5.000", "2.625", "25.0%", "0"});
  CHECK(row(r.output, "solve") == std::vector<std::string>{"5.000", "9.500", "10.000", "10.000", "5.250", "50.0%", "0"});
  CHECK(row(r.output, "untimed") == std::vector<std::string>{"2.500", "4.750", "5.000", "5.000", "2.625", "25.0%"});
  CHECK(row(r.output, "iterations.pgs") == std::vector<std::string>{"10", "19", "20", "20", "10.5"});
  CHECK(row(r.output, "rows.contact") == std::vector<std::string>{"4", "4", "4", "4", "4.0"});
  // Pipeline order (engine/profile.hpp), not the file's alphabetical order.
  CHECK(r.output.find("assemble") < r.output.find("solve"));
}

TEST_CASE("sinew profile: null times (a run that went non-finite) are left out of their row") {
  TempDir dir("profile_null");
  const std::string stats = dir.write(
      "stats.json",
      R"({"frames": [{"step_ms": 3, "stages": {"solve": 3}}, {"step_ms": 1, "stages": {"solve": 1}},
                     {"step_ms": null, "stages": {"solve": null}, "finite": false},
                     {"step_ms": 2, "stages": {"solve": 2}}]})");
  const auto r = run_sinew("profile " + stats);
  INFO(r.output);
  REQUIRE(r.code == 0);
  CHECK(r.output.find("1 not finite") != std::string::npos);
  CHECK(row(r.output, "step (frame)")[0] == "2.000");  // median of {1, 2, 3}
  CHECK(row(r.output, "step (frame)")[3] == "3.000");
}

TEST_CASE("sinew profile: --plot draws a PNG of the requested size in the stage colours, --csv one row per frame") {
  TempDir dir("profile_plot");
  const std::string stats = dir.write("stats.json", synthetic_stats());
  const auto r = run_sinew("profile " + stats + " --plot " + (dir / "p.png") + " --csv " + (dir / "p.csv") +
                           " --size 640x480");
  INFO(r.output);
  REQUIRE(r.code == 0);
  const sinew::Image image = sinew::read_png(dir / "p.png");
  CHECK(image.width == 640);
  CHECK(image.height == 480);
  // Chart series in pipeline order: assemble, solve, untimed; each a real area, not a swatch.
  for (int s = 0; s < 3; ++s) CHECK(count_color(image, sinew::plot::series_color(s)) > 500);
  CHECK(count_color(image, sinew::plot::kInk) > 500);  // axes, ticks and text

  std::ifstream csv(dir / "p.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  REQUIRE(lines.size() == 21);
  CHECK(lines[0] == "frame,t,step_ms,assemble_ms,solve_ms,untimed_ms,rows.contact,iterations.pgs,finite");
  CHECK(lines[2] == "2,0.02,8,2,4,2,4,8,true");
}

TEST_CASE("sinew profile: --help documents every option") {
  const auto r = run_sinew("profile --help");
  CHECK(r.code == 0);
  for (const char* word : {"--plot OUT.png", "--csv OUT.csv", "--size WxH", "nearest-rank", "p95", "p99"})
    CHECK_MESSAGE(r.output.find(word) != std::string::npos, word);
  CHECK(run_sinew("--help").output.find("profile STATS") != std::string::npos);
}

TEST_CASE("sinew profile: bad input exits 2 naming the file and JSON path, and writes nothing") {
  struct Case {
    std::string name, text, path, words;
  };
  const std::vector<Case> cases = {
      {"not JSON", "{\"frames\": [", "", "is not JSON"},
      {"not an object", "[1, 2]", "at /:", "expected an object"},
      {"no frames", R"({"summary": {}})", "/frames", "missing"},
      {"frames not an array", R"({"frames": {}})", "/frames", "expected an array"},
      {"empty frames", R"({"frames": []})", "/frames", "nothing to profile"},
      {"frame without step_ms", R"({"frames": [{"step_ms": 1, "stages": {}}, {"stages": {}}]})", "/frames/1/step_ms",
       "missing"},
      {"frame without stages", R"({"frames": [{"step_ms": 1}]})", "/frames/0/stages", "missing"},
      {"stage time not a number", R"({"frames": [{"step_ms": 1, "stages": {"assemble": "fast"}}]})",
       "/frames/0/stages/assemble", "expected a number"},
      {"count not a number", R"({"frames": [{"step_ms": 1, "stages": {}, "rows": {"contact": [1]}}]})",
       "/frames/0/rows/contact", "expected a count"},
      {"bad summary", R"({"frames": [{"step_ms": 1, "stages": {}}], "summary": {"steps_per_frame": 0}})",
       "/summary/steps_per_frame", "expected an integer"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    TempDir dir("profile_bad");
    const std::string stats = dir.write("stats.json", c.text);
    const auto r = run_sinew("profile " + stats + " --plot " + (dir / "p.png") + " --csv " + (dir / "p.csv"));
    INFO(r.output);
    CHECK(r.code == 2);
    CHECK(r.output.find(stats) != std::string::npos);
    CHECK(r.output.find(c.path) != std::string::npos);
    CHECK(r.output.find(c.words) != std::string::npos);
    CHECK(other_files(dir.path, "stats.json") == 0);
  }

  TempDir dir("profile_missing");
  const auto r = run_sinew("profile " + (dir / "nope.json") + " --plot " + (dir / "p.png"));
  CHECK(r.code == 2);
  CHECK(r.output.find(dir / "nope.json") != std::string::npos);
  CHECK(r.output.find("no such file") != std::string::npos);
  CHECK(fs::is_empty(dir.path));

  const std::string stats = dir.write("stats.json", synthetic_stats());
  CHECK(run_sinew("profile " + stats + " --size 10x10 --plot " + (dir / "p.png")).code == 2);
  CHECK(run_sinew("profile " + stats + " --bogus").code == 2);
  CHECK(run_sinew("profile").code == 2);
  // An output folder that does not exist: a clear error, exit 2, no CSV left behind either.
  const auto out = run_sinew("profile " + stats + " --csv " + (dir / "p.csv") + " --plot " + (dir / "no/p.png"));
  CHECK(out.code == 2);
  CHECK(out.output.find("no/p.png") != std::string::npos);
  CHECK(other_files(dir.path, "stats.json") == 0);
}

TEST_CASE("sinew profile: a real run of a shipped scene, end to end") {
  TempDir dir("profile_real");
  const std::string scene = std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_beam_150kPa.json";
  const auto run = run_sinew("run " + scene + " --frames 5 --quiet --stats " + (dir / "s.json"));
  INFO(run.output);
  REQUIRE(run.code == 0);
  const auto r = run_sinew("profile " + (dir / "s.json") + " --plot " + (dir / "p.png") + " --csv " + (dir / "p.csv"));
  INFO(r.output);
  REQUIRE(r.code == 0);
  CHECK(r.output.find("5 frames") != std::string::npos);
  for (const char* stage : {"step (frame)", "assemble", "factorize", "solve", "integrate", "surface", "untimed"})
    CHECK_MESSAGE(row(r.output, stage).size() >= 6, stage);
  const sinew::Image image = sinew::read_png(dir / "p.png");
  CHECK(image.width == 1200);
  CHECK(image.height == 900);
  CHECK(count_color(image, sinew::plot::series_color(0)) > 100);  // assemble
  CHECK(fs::exists(dir / "p.csv"));
}
