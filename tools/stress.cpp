// sinew_stress: the stress suite of issue 10, section 2. Each case drives the engine into a
// hard corner (scrambled bodies, hits, huge steps, near-incompressibility, conflicting
// constraints, bad meshes, long runs) and ends with one verdict line:
//   stress NAME: PASS|FAIL what was checked and the worst figures (seconds)
// The exit code is 1 if any case failed, 2 on bad usage. `--quick` is the reduced run that
// CI makes (ctest stress_quick); without it, the full run. Deterministic: fixed seeds.
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "engine/io/atomic_file.hpp"
#include "tools/stress/collapse.hpp"
#include "tools/stress/crush_release.hpp"
#include "tools/stress/degenerate_mesh.hpp"
#include "tools/stress/incompressible.hpp"
#include "tools/stress/large_step.hpp"
#include "tools/stress/perturbed_scenes.hpp"
#include "tools/stress/scrambled_cubes.hpp"
#include "tools/stress/soak.hpp"

using namespace sinew;
using namespace sinew::stress;

namespace {

struct Case {
  const char* name;
  const char* what;  // for --help
  std::function<CaseResult(const Options&)> run;
};

const std::vector<Case> kCases = {
    {"scrambled_cubes", "Stable Neo-Hookean cubes (hex8, mean dilatation) with scrambled nodes, 10 steps of 0.5 s (500; quick 20)",
     run_scrambled_cubes},
    {"perturbed_scenes", "every paper scene hit by random node moves and velocity kicks (quick: 8 scenes, 30 steps)",
     run_perturbed_scenes},
    {"large_step", "beam and creature scenes at h = 1/10 s (quick: 3 scenes)", run_large_step},
    {"incompressible", "nu 0.499: corotational hex/tet and Stable Neo-Hookean, cantilever and drop",
     run_incompressible},
    {"collapse_U50", "paper 000 collapsing sphere, E 50 kPa, Umax 50 J", run_collapse},
    {"crush_release", "a ball crushed flat by a kinematic plate and released (full: also under an energy limit)",
     run_crush_release},
    {"degenerate_mesh", "TetGen/Gmsh files with flat, inverted, folded and sliver tets", run_degenerate_mesh},
    {"soak", "10,000 steps (quick 1,000) of two small scenes; resident memory must not grow", run_soak},
};

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: sinew_stress [--quick] [--only CASE] [--out FILE.json] [--help]\n"
               "  --quick      the reduced run CI makes (under 2 minutes); default: the full run\n"
               "  --only CASE  run one case\n"
               "  --out FILE   write every case's verdict and figures as JSON (whole or not at all)\n"
               "cases:\n");
  for (const Case& c : kCases) std::fprintf(out, "  %-17s %s\n", c.name, c.what);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::string only, out;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") options.quick = true;
    else if (arg == "--only" && i + 1 < argc) only = argv[++i];
    else if (arg == "--out" && i + 1 < argc) out = argv[++i];
    else if (arg == "--help" || arg == "-h") return usage(stdout), 0;
    else return usage(stderr), 2;
  }
  if (!only.empty() && std::none_of(kCases.begin(), kCases.end(), [&](const Case& c) { return only == c.name; })) {
    std::fprintf(stderr, "sinew_stress: no case '%s'\n", only.c_str());
    return usage(stderr), 2;
  }

  // Fail before a long run, not after it, when the results could not be written.
  if (const auto folder = std::filesystem::path(out).parent_path(); !out.empty() && !folder.empty() &&
                                                                     !std::filesystem::is_directory(folder)) {
    std::fprintf(stderr, "sinew_stress: --out %s: no folder %s\n", out.c_str(), folder.c_str());
    return 2;
  }

  const auto start = std::chrono::steady_clock::now();
  nlohmann::json results = {{"mode", options.quick ? "quick" : "full"}, {"cases", nlohmann::json::array()}};
  std::vector<std::string> verdicts;
  int failed = 0;
  for (const Case& c : kCases) {
    if (!only.empty() && only != c.name) continue;
    std::printf("stress %s: running (%s)\n", c.name, c.what);
    std::fflush(stdout);
    const auto case_start = std::chrono::steady_clock::now();
    CaseResult r;
    // An exception is a failed case, not the end of the suite.
    try {
      r = c.run(options);
    } catch (const std::exception& e) {
      r.pass = false;
      r.summary = std::string("threw: ") + e.what();
    }
    const double seconds = seconds_since(case_start);
    failed += !r.pass;
    verdicts.push_back(format("stress %s: %s ", c.name, r.pass ? "PASS" : "FAIL") + r.summary +
                       format(" (%.1f s)", seconds));
    std::printf("%s\n", verdicts.back().c_str());
    std::fflush(stdout);
    results["cases"].push_back({{"name", c.name}, {"pass", r.pass}, {"verdict", verdicts.back()},
                                {"seconds", seconds}, {"details", r.details}});
  }
  const double total = seconds_since(start);
  // The verdicts again, together, so that a long log ends with the whole picture.
  std::printf("\nstress summary (%s run, %.1f s):\n", options.quick ? "quick" : "full", total);
  for (const std::string& v : verdicts) std::printf("  %s\n", v.c_str());
  std::printf("stress: %s, %d of %zu cases failed\n", failed ? "FAILED" : "all passed", failed, verdicts.size());
  results["failed"] = failed;
  results["seconds"] = total;
  if (!out.empty()) {
    try {
      write_file_atomically(out, [&](std::ostream& o) { o << results.dump(2) << "\n"; });
      std::printf("wrote %s\n", out.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sinew_stress: %s\n", e.what());
      return 1;
    }
  }
  return failed ? 1 : 0;
}
