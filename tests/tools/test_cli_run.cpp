// `sinew run` as a user meets it: bad scenes give a clear message naming the file and JSON
// path, a non-zero exit code, and no output files.
#include <doctest/doctest.h>

#include "tests/support/cli_runner.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using Result = sinew::test::CliResult;
using sinew::test::run_sinew;
using sinew::test::TempDir;

const char* kGoodBody = R"("name": "b", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1)";

std::string scene_with(const std::string& body_extra, const std::string& top_extra = "",
                       const std::string& material = R"({"E": 1e5, "nu": 0.3, "rho": 1000})") {
  return "{" + top_extra + R"("frames": 2, "bodies": [{)" + kGoodBody + R"(, "material": )" + material +
         body_extra + "}]}";
}

// Runs a bad scene with every output option and checks the error and that nothing was written.
void expect_input_error(const std::string& scene_text, const std::string& expected_path,
                        const std::string& expected_words) {
  TempDir dir("bad");
  const std::string scene = dir.write("scene.json", scene_text);
  const fs::path out = dir.path / "out";
  const Result r = run_sinew("run " + scene + " --stats " + (out / "stats.json").string() + " --export-obj " +
                             (out / "obj").string() + " --export-vtu " + (out / "vtu").string());
  INFO("output: " << r.output);
  CHECK(r.code == 2);
  CHECK(r.output.find(scene) != std::string::npos);
  CHECK(r.output.find(expected_path) != std::string::npos);
  CHECK(r.output.find(expected_words) != std::string::npos);
  CHECK(!fs::exists(out));
}

}  // namespace

TEST_CASE("sinew run: a good scene runs, writes stats and exports, exits 0") {
  TempDir dir("good");
  const std::string scene = dir.write("scene.json", scene_with(""));
  const Result r = run_sinew("run " + scene + " --stats " + (dir.path / "s.json").string() + " --export-obj " +
                             (dir.path / "obj").string() + " --export-vtu " + (dir.path / "vtu").string());
  INFO(r.output);
  CHECK(r.code == 0);
  CHECK(r.output.find("median ms") != std::string::npos);
  CHECK(fs::exists(dir.path / "s.json"));
  CHECK(fs::exists(dir.path / "obj" / "b_00002.obj"));
  CHECK(fs::exists(dir.path / "vtu" / "b_00002.vtu"));
  CHECK(fs::exists(dir.path / "vtu" / "b.pvd"));
}

TEST_CASE("sinew run: each bad scene names the file and JSON path, exits 2, writes nothing") {
  expect_input_error(scene_with(R"(, "celsize": 1)"), "bodies[0].celsize", "did you mean 'cell_size'");
  expect_input_error(scene_with("", "", R"({"E": "soft", "nu": 0.3, "rho": 1000})"), "bodies[0].material.E",
                     "expected a number");
  expect_input_error(scene_with("", "", R"({"E": -5, "nu": 0.3, "rho": 1000})"), "bodies[0].material.E", "> 0");
  expect_input_error(scene_with("", "", R"({"E": 1e5, "nu": 0.5, "rho": 1000})"), "bodies[0].material.nu", "0.5");
  expect_input_error(scene_with("", "", R"({"E": 1e5, "nu": -0.1, "rho": 1000})"), "bodies[0].material.nu", "0");
  expect_input_error(scene_with("", "", R"({"E": 1e5, "nu": 0.3, "rho": 0})"), "bodies[0].material.rho", "> 0");
  expect_input_error(scene_with("", R"("h": 0, )"), "h", "> 0");
  expect_input_error(R"({"bodies": [{"name": "m", "mesh": "missing.obj", "cell_size": 0.1,
                       "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})",
                     "bodies[0].mesh", "not found");
  // A degenerate shape (it would give an empty lattice) is refused by the parser.
  expect_input_error(R"({"bodies": [{"name": "e", "shape": [{"type": "box", "half_extents": [0, 0, 0]}],
                       "cell_size": 0.1, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})",
                     "bodies[0].shape[0].half_extents", "> 0");
}

TEST_CASE("sinew run: a mesh that is not closed gets a warning and still runs") {
  TempDir dir("open");
  // A tetrahedron with one face missing.
  dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");
  const std::string scene = dir.write("scene.json", R"({"frames": 1, "bodies": [{"name": "o", "mesh": "open.obj",
      "cell_size": 0.25, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})");
  const Result r = run_sinew("run " + scene + " --quiet");
  INFO(r.output);
  CHECK(r.output.find("warning") != std::string::npos);
  CHECK(r.output.find("not closed") != std::string::npos);
  CHECK(r.code == 0);
}

TEST_CASE("sinew run: unreadable scene and bad options") {
  Result r = run_sinew("run /nonexistent/scene.json");
  CHECK(r.code == 2);
  CHECK(r.output.find("/nonexistent/scene.json") != std::string::npos);
  r = run_sinew("run a.json --frames zero");
  CHECK(r.code == 2);
  CHECK(r.output.find("--frames") != std::string::npos);
  r = run_sinew("run a.json --bogus");
  CHECK(r.code == 2);
  CHECK(r.output.find("unknown option '--bogus'") != std::string::npos);
  r = run_sinew("run a.json --cpu-placement best");
  CHECK(r.code == 2);
  CHECK(r.output.find("--cpu-placement") != std::string::npos);
  r = run_sinew("run --help");
  CHECK(r.code == 0);
  for (const char* option : {"--frames", "--threads", "--stats", "--export-obj", "--export-vtu", "--quiet", "--cpu-placement"})
    CHECK(r.output.find(option) != std::string::npos);
}

TEST_CASE("sinew run: the CPUs' probe times in the output and the stats summary; none pins nothing") {
  TempDir dir("placement");
  const std::string scene = dir.write("scene.json", scene_with(""));
  const std::string stats = (dir.path / "s.json").string();
  const Result r = run_sinew("run " + scene + " --cpu-placement none --stats " + stats);
  INFO(r.output);
  REQUIRE(r.code == 0);
  CHECK(r.output.find("main thread left to the scheduler") != std::string::npos);
  std::ifstream in(stats);
  const nlohmann::json summary = nlohmann::json::parse(in)["summary"];
  CHECK(summary["cpu_placement"] == "none");
  CHECK(summary["cpu_pinned"] == -1);
  // One positive time per CPU the run may use (it inherits this process's set), when there
  // are 2 to 16 of them; else none.
  cpu_set_t set;
  CPU_ZERO(&set);
  REQUIRE(sched_getaffinity(0, sizeof set, &set) == 0);
  const int cpus = CPU_COUNT(&set);
  const auto& probes = summary["cpu_probe_ms"];
  REQUIRE(probes.is_object());
  if (cpus >= 2 && cpus <= 16)
    CHECK(static_cast<int>(probes.size()) == cpus);
  else
    CHECK(probes.empty());
  for (const auto& [cpu, ms] : probes.items()) {
    CHECK(CPU_ISSET(std::stoi(cpu), &set));
    CHECK(ms.get<double>() > 0);
  }
}
