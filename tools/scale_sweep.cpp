// sinew_scale_sweep: how the cost of a step grows with the element count, per stage, and
// what a second thread buys each stage (issue 7, section 5). A block of 100 to 20,000
// hexahedra rests on a ground plane with an energy limit (tools/scale_sweep/lattice_scene.*);
// each size is stepped at every thread count in turn (tools/scale_sweep/measure.*); medians
// per stage, speedups, JSON and two charts (tools/scale_sweep/report.*). Progress on stderr,
// a table on stdout. README "Benchmarks" and bench/results/README.md say how it was run.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/profile.hpp"
#include "engine/io/stats_summary.hpp"
#include "tools/bench_common.hpp"
#include "tools/scale_sweep/report.hpp"

using namespace sinew;
using namespace sinew::sweep;

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
      "usage: sinew_scale_sweep [--sizes N,N,...] [--steps N] [--warmup N] [--budget S]\n"
      "                         [--threads-list T,T,...] [--energy-limit D] [--out DIR] [--quick] [--help]\n"
      "Times a block of hexahedra resting on a ground plane with an energy limit, at each size and\n"
      "thread count: per-stage medians, DOFs, constraint rows, SQP/PGS iterations, speedups.\n"
      "  --sizes N,...        target hexahedron counts (default 100,300,1000,3000,10000,20000); each\n"
      "                       becomes the nearest nx x k x k block (k = round(cbrt(N/2)))\n"
      "  --steps N            timed steps per size and thread count, at most (default 30)\n"
      "  --warmup N           untimed steps first, the start of the sag (default 10)\n"
      "  --budget S           seconds of timed stepping per size, all thread counts together; a size\n"
      "                       whose steps do not fit takes fewer, at least 3 (default 120)\n"
      "  --threads-list T,... thread counts to compare, the first being the base of the speedups\n"
      "                       (default 1,2)\n"
      "  --energy-limit D     the energy limit as a density, J/m^3: each element's Umax is D times its\n"
      "                       volume (default 600; the static density at the bottom is ~120)\n"
      "  --out DIR            where scale_sweep.json, stage_times.png and speedup.png go, rewritten\n"
      "                       after each size (\"complete\": false until the last) (default out/scale_sweep)\n"
      "  --quick              a smoke run of seconds: sizes 50,100,200, 3 steps, 3 warm-up steps\n"
      "                       (options given with it still apply)\n"
      "  --help               this text\n"
      "Exit codes: 0 done, 1 internal error, 2 bad usage, 3 a step was refused (outputs still written).\n");
}

// The whole of `text` as a number (a whole one when `whole`) for which `ok` holds, else an
// error naming the option and what it expects.
double parse_number(const std::string& option, const std::string& text, bool whole, const std::string& expected,
                    const std::function<bool(double)>& ok) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value) || (whole && value != std::floor(value)) || !ok(value))
    throw std::invalid_argument(option + " expects " + expected + ", got '" + text + "'");
  return value;
}

int parse_count(const std::string& option, const std::string& text, int min) {
  return static_cast<int>(parse_number(option, text, true, "a whole number >= " + std::to_string(min),
                                       [&](double v) { return v >= min && v <= 1e9; }));
}

double parse_positive(const std::string& option, const std::string& text, const std::string& what) {
  return parse_number(option, text, false, what + " > 0", [](double v) { return v > 0; });
}

std::vector<int> parse_list(const std::string& option, const std::string& text, int min) {
  std::vector<int> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(parse_count(option, item, min));
  if (out.empty() || text.back() == ',') throw std::invalid_argument(option + " expects a comma-separated list, got '" + text + "'");
  return out;
}

struct Parsed {
  SweepOptions sweep;
  std::string out = "out/scale_sweep", command = "sinew_scale_sweep";
  bool help = false;
};

// --quick sets its defaults first; every option given explicitly wins over them.
Parsed parse(int argc, char** argv) {
  Parsed p;
  std::optional<std::vector<int>> sizes, threads;
  std::optional<int> steps, warmup;
  std::optional<double> budget, energy_limit;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    p.command += " " + arg;
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      p.command += std::string(" ") + argv[i + 1];
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") p.help = true;
    else if (arg == "--quick") p.sweep.quick = true;
    else if (arg == "--sizes") sizes = parse_list(arg, value(), 1);
    else if (arg == "--threads-list") threads = parse_list(arg, value(), 1);
    else if (arg == "--steps") steps = parse_count(arg, value(), 1);
    else if (arg == "--warmup") warmup = parse_count(arg, value(), 0);
    else if (arg == "--budget") budget = parse_positive(arg, value(), "a number of seconds");
    else if (arg == "--energy-limit") energy_limit = parse_positive(arg, value(), "an energy density (J/m^3)");
    else if (arg == "--out") p.out = value();
    else throw std::invalid_argument("unknown option '" + arg + "'");
  }
  if (p.sweep.quick) {
    p.sweep.sizes = {50, 100, 200};
    p.sweep.steps = p.sweep.warmup = 3;
  }
  if (sizes) p.sweep.sizes = *sizes;
  if (threads) p.sweep.threads = *threads;
  if (steps) p.sweep.steps = *steps;
  if (warmup) p.sweep.warmup = *warmup;
  if (budget) p.sweep.budget = *budget;
  if (energy_limit) p.sweep.block.energy_density_limit = *energy_limit;
  std::sort(p.sweep.sizes.begin(), p.sweep.sizes.end());
  if (std::adjacent_find(p.sweep.sizes.begin(), p.sweep.sizes.end()) != p.sweep.sizes.end())
    throw std::invalid_argument("--sizes lists a size twice");
  std::vector<int> t = p.sweep.threads;
  std::sort(t.begin(), t.end());
  if (std::adjacent_find(t.begin(), t.end()) != t.end())
    throw std::invalid_argument("--threads-list lists a thread count twice");
  return p;
}

std::string joined(const std::vector<int>& v) {
  std::string out;
  for (int x : v) out += (out.empty() ? "" : ",") + std::to_string(x);
  return out;
}

// One line per size and thread count: medians of the step and its main stages, and counts.
void print_table(const std::vector<SizeResult>& sizes) {
  std::printf("%8s %8s %7s %5s %10s %10s %10s %10s %10s %9s %6s %6s\n", "hex", "DOFs", "threads", "rows", "step",
              "assemble", "factorize", "solve", "constraint", "surface", "sqp", "pgs");
  for (const SizeResult& s : sizes)
    for (const ThreadRun& r : s.runs) {
      double constraint = 0;  // sum of the constraint stages' medians
      for (int st = 0; st < kStageCount; ++st)
        if (const auto stage = static_cast<Stage>(st); is_constraint_stage(stage))
          constraint += median_ms(r, stage_name(stage));
      std::printf("%8d %8d %7d %5.0f %10.2f %10.2f %10.2f %10.2f %10.2f %9.3f %6.0f %6.0f\n", s.elements, s.dofs,
                  r.threads, quantile(bench::row_totals(r.samples), 0.5), median_ms(r, "step"),
                  median_ms(r, "assemble"), median_ms(r, "factorize"), median_ms(r, "solve"), constraint,
                  median_ms(r, "surface"), quantile(bench::iteration_counts(r.samples, "sqp"), 0.5),
                  quantile(bench::iteration_counts(r.samples, "pgs"), 0.5));
    }
  std::printf("(ms per step, medians; constraint = sum of the medians of rows, sqp_factorize, sqp_solve, pgs, sqp_merit)\n");
}

}  // namespace

int main(int argc, char** argv) {
  Parsed p;
  try {
    p = parse(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinew_scale_sweep: %s (see --help)\n", e.what());
    return 2;
  }
  if (p.help) return usage(stdout), 0;
  const SweepOptions& o = p.sweep;

  RunInfo info;
  info.command = p.command;
  info.date_utc = bench::utc_now();
  info.cpu = bench::cpu_model();
  info.processors = bench::processor_count();
  info.load_start = bench::load_average();
  const auto start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "sinew_scale_sweep: sizes %s, threads %s, %d warm-up + up to %d timed steps; %d processors, "
               "load average %.2f %.2f %.2f\n", joined(o.sizes).c_str(), joined(o.threads).c_str(), o.warmup, o.steps,
               info.processors, info.load_start[0], info.load_start[1], info.load_start[2]);
  for (int t : o.threads)
    if (t > info.processors)
      std::fprintf(stderr, "sinew_scale_sweep: warning: %d threads on %d processors (oversubscribed)\n", t,
                   info.processors);

  std::vector<SizeResult> results;
  bool finite = true;
  // The outputs so far, after each size: a long run that is stopped keeps what it measured.
  auto write_outputs = [&](bool complete) {
    info.load_end = bench::load_average();
    info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ensure_directory(p.out);
    write_file_atomically(p.out + "/scale_sweep.json", [&](std::ostream& s) {
      nlohmann::json json = sweep_json(results, o, info);
      json["complete"] = complete;
      s << json.dump(1) << "\n";
    });
    write_stage_chart(results, p.out + "/stage_times.png");
    write_speedup_chart(results, p.out + "/speedup.png");
  };
  try {
    for (size_t i = 0; i < o.sizes.size(); ++i) {
      const auto size_start = std::chrono::steady_clock::now();
      const std::string prefix = "[" + std::to_string(i + 1) + "/" + std::to_string(o.sizes.size()) + " size " +
                                 std::to_string(o.sizes[i]) + "] ";
      results.push_back(measure_size(o.sizes[i], o, [&](const std::string& line) {
        std::fprintf(stderr, "%s%s\n", prefix.c_str(), line.c_str());
      }));
      for (const ThreadRun& r : results.back().runs) finite = finite && r.finite;
      if (!results.back().hashes_equal())
        std::fprintf(stderr, "%swarning: the thread counts ended in different states\n", prefix.c_str());
      write_outputs(i + 1 == o.sizes.size());
      std::fprintf(stderr, "%sdone in %.0f s; outputs written\n", prefix.c_str(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - size_start).count());
    }
    print_table(results);
    std::fprintf(stderr, "sinew_scale_sweep: wrote scale_sweep.json, stage_times.png%s in %s (%.1f min; load average "
                 "at the end %.2f %.2f %.2f)\n", o.threads.size() > 1 ? " and speedup.png" : "", p.out.c_str(),
                 info.wall_seconds / 60, info.load_end[0], info.load_end[1], info.load_end[2]);
  } catch (const InputError& e) {
    std::fprintf(stderr, "sinew_scale_sweep: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinew_scale_sweep: %s\n", e.what());
    return 1;
  }
  return finite ? 0 : 3;
}
