// sinew_work_precision: run time against error (issue 10, section 1). For each family of
// paper scenes (tools/work_precision/families.cpp) and each method variant, sweeps what
// trades time for error (h, PGS cap, SQP / strain / contact / Newton / PCG tolerances,
// lattice resolution), measures each point's wall time per simulated second and its error
// against a converged reference of the same scene (h / 16, tight tolerances; cached on disk),
// and writes the data as JSON, a log-log chart per family and a Markdown summary with the
// papers' comparisons. Progress goes to stderr. README "Work-precision" says how to run it.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <sstream>
#include <thread>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "tools/cli_options.hpp"
#include "tools/work_precision/report.hpp"

using namespace sinew;
using namespace sinew::wp;

namespace {

struct Options {
  bool quick = false, fresh = false;
  std::string out = "out/work_precision";
  std::string cache = std::string(SINEW_BINARY_DIR) + "/work_precision_cache";
  std::vector<std::string> only;
  int threads = 1;
};

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: sinew_work_precision [--quick] [--out DIR] [--only FAMILY[,FAMILY...]] [--threads T]\n"
               "                            [--cache DIR] [--fresh] [--help]\n"
               "  --quick          the reduced run (fewer points, half the simulated time; a few minutes)\n"
               "  --out DIR        where work_precision.json, work_precision.md and FAMILY.png go\n"
               "                   (default out/work_precision)\n"
               "  --only FAMILY    run these families only (comma-separated)\n"
               "  --threads T      worker threads for the simulations (default 1: timings of one core)\n"
               "  --cache DIR      converged references kept here (default BUILD/work_precision_cache)\n"
               "  --fresh          recompute the references even when cached (after an engine change)\n"
               "families:\n");
  for (const Family& f : make_families())
    std::fprintf(out, "  %-18s %s%s\n", f.name.c_str(), f.description.c_str(), f.in_default_run ? "" : " (only with --only)");
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  char s[32];
  std::strftime(s, sizeof s, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return s;
}

std::string machine() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string model = "unknown CPU";
  for (std::string line; std::getline(cpu, line);)
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores";
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string command = "sinew_work_precision";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    command += " " + arg;
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      command += std::string(" ") + argv[i + 1];
      return argv[++i];
    };
    try {
      if (arg == "--quick") o.quick = true;
      else if (arg == "--fresh") o.fresh = true;
      else if (arg == "--out") o.out = value();
      else if (arg == "--cache") o.cache = value();
      else if (arg == "--only") o.only = split(value());
      else if (arg == "--threads") o.threads = cli::parse_int(value(), "option --threads", 1);
      else if (arg == "--help" || arg == "-h") return usage(stdout), 0;
      else throw std::invalid_argument("unknown option " + arg);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sinew_work_precision: %s (see --help)\n", e.what());
      return 2;
    }
  }
  std::vector<Family> families;
  for (Family& f : make_families())
    if (o.only.empty() ? f.in_default_run : std::find(o.only.begin(), o.only.end(), f.name) != o.only.end())
      families.push_back(std::move(f));
  if (families.size() != (o.only.empty() ? families.size() : o.only.size())) {
    std::fprintf(stderr, "sinew_work_precision: unknown family in --only\n");
    return usage(stderr), 2;
  }

  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, o.threads);
  const auto start = std::chrono::steady_clock::now();
  try {
    StudyOptions study{o.quick, o.fresh, o.cache, std::string(SINEW_SOURCE_DIR) + "/assets/scenes"};
    std::vector<FamilyResult> results;
    for (const Family& f : families) results.push_back(run_family(f, study));

    RunInfo info{command, utc_now(), machine(), o.quick, o.threads,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
    ensure_directory(o.out);
    write_file_atomically(o.out + "/work_precision.json",
                          [&](std::ostream& s) { s << to_json(results, info).dump(1) << "\n"; });
    for (const FamilyResult& f : results) write_family_chart(f, o.out + "/" + f.name + ".png");
    write_file_atomically(o.out + "/work_precision.md", [&](std::ostream& s) { s << markdown_summary(results, info); });
    std::fprintf(stderr, "wrote %s/work_precision.json, work_precision.md and %zu charts (%.1f min)\n", o.out.c_str(),
                 results.size(), info.total_seconds / 60);
  } catch (const InputError& e) {
    std::fprintf(stderr, "sinew_work_precision: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinew_work_precision: %s\n", e.what());
    return 1;
  }
  return 0;
}
