// sinew_bench: times steps of named scenes, per stage; medians, optionally over repeated
// runs, JSON out. Warm-up steps are excluded. Speed lives here, never in unit tests.
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/simulate_frame.hpp"
#include "tools/bench_common.hpp"
#include "tools/cli_options.hpp"

using namespace sinew;

namespace {

struct BenchScene {
  std::string name;
  std::function<SceneDesc()> make;  // throws if unavailable (e.g. a missing shared mesh)
  // Sleeping bodies stay off (solver.sleep_steps 0) so that the figures time the simulation
  // of every scene even once it rests; scenes that measure sleeping turn it on and settle
  // for extra warm-up steps first.
  bool sleeping = false;
  int settle = 0;
};

std::string source_dir() { return SINEW_SOURCE_DIR; }

SceneDesc scene_file(const std::string& relative) { return load_scene(source_dir() + "/" + relative); }

// The armadillo of paper 000, fig. 6: 2 m tall, ~365 cells, lying free under gravity.
SceneDesc armadillo_scene() {
  const std::string mesh = source_dir() + "/../shared/meshes/armadillo.obj";
  if (!std::filesystem::exists(mesh)) throw InputError("armadillo mesh not found at " + mesh);
  const std::string text = R"({"name": "armadillo365", "h": 0.0166667,
    "bodies": [{"name": "armadillo", "mesh": ")" + mesh + R"(",
      "transform": {"scale": 2.0},
      "cell_size": 0.163,
      "material": {"E": 5e5, "nu": 0.3, "rho": 500}, "damping": {"stiffness": 0.01},
      "fixed": [{"half_space": {"point": [0, -1.0, 0], "normal": [0, 1, 0]}}]}]})";
  return parse_scene_text(text, "armadillo365", source_dir());
}

// A 40 x 25 x 10 block of 10,000 cells fixed at one end.
SceneDesc block10k_scene() {
  const std::string text = R"({"name": "block10k", "h": 0.0166667,
    "bodies": [{"name": "block", "shape": [{"type": "box", "half_extents": [1.0, 0.625, 0.25]}],
      "cell_size": 0.05, "material": {"E": 1e6, "nu": 0.3, "rho": 1000},
      "damping": {"stiffness": 0.01},
      "fixed": [{"half_space": {"point": [-0.99, 0, 0], "normal": [1, 0, 0]}}]}]})";
  return parse_scene_text(text, "block10k", source_dir());
}

// Three 0.34 m boxes (64 cells each) resting on a plane: the cost of a scene at rest, awake
// and asleep (docs/ARCHITECTURE.md, "Sleeping bodies").
SceneDesc rest_boxes_scene() {
  std::string bodies;
  for (int i = 0; i < 3; ++i)
    bodies += std::string(i ? ", " : "") + R"({"name": "box)" + std::to_string(i) +
              R"(", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}], "transform": {"translate": [)" +
              std::to_string(0.8 * (i - 1)) + R"(, 0.175, 0]}, "cell_size": 0.1, "surface_resolution": 0.085,
      "material": {"E": 1e6, "nu": 0.3, "rho": 500}})";
  return parse_scene_text(R"({"name": "rest3boxes", "h": 0.0166667, "bodies": [)" + bodies +
                              R"(], "obstacles": [{"type": "plane", "friction": 0.5}]})",
                          "rest3boxes", source_dir());
}

std::vector<BenchScene> all_scenes() {
  return {{"beam56", [] { return scene_file("assets/scenes/paper000_beam_150kPa.json"); }},
          {"armadillo365", armadillo_scene},
          {"block10k", block10k_scene},
          // Paper 000, fig. 6: ~365 hex, energy limits (100 J) and ground contact.
          {"creature365", [] { return scene_file("assets/scenes/paper000_creature_500kPa_U100.json"); }},
          // Paper 001: the fig. 2 beam (240 tets) and the fig. 3 finger pressed on its side
          // (324 tets, hundreds of active strain limits and ground contact).
          {"beam240tet", [] { return scene_file("assets/scenes/paper001_beam_5kPa_anisotropic.json"); }},
          {"finger324", [] { return scene_file("assets/scenes/paper001_finger_side_anisotropic.json"); }},
          // The same finger pressed flat: issue 5's benchmark (> 40 constrained tets).
          {"finger324flat", [] { return scene_file("assets/scenes/paper001_finger_flat_anisotropic.json"); }},
          // Sleeping (issue 7): the boxes fall asleep ~40 steps after they land.
          {"rest3boxes_awake", rest_boxes_scene, false, 60},
          {"rest3boxes_asleep", rest_boxes_scene, true, 60}};
}

// A scene file as a benchmark, named after the file. Loaded up front (`loaded`), so that a
// bad file stops the run before anything is timed or written.
BenchScene file_scene(const std::string& path) {
  SceneDesc loaded = load_scene(path);
  return {std::filesystem::path(path).stem().string(), [loaded] { return loaded; }};
}

// Every assets/scenes/paper*.json, by name: issue 7's "steps per second of every paper scene".
std::vector<std::string> paper_scene_files() {
  const std::string folder = source_dir() + "/assets/scenes";
  std::vector<std::string> files;
  std::error_code error;
  for (std::filesystem::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("paper", 0) == 0 && it->path().extension() == ".json") files.push_back(it->path().string());
  }
  if (error) throw InputError(folder + ": " + error.message());
  if (files.empty()) throw InputError(folder + ": no paper*.json scene");
  std::sort(files.begin(), files.end());
  return files;
}

// Tets holding an active strain limit (a row with lambda > 0) at the end of the step: the
// "constrained tets" of paper 001's timings. Read from the multipliers the step keeps as the
// next one's warm start (solve_constraints), since the row table itself is rebuilt, without
// multipliers, by the SQP iteration that finds convergence.
int constrained_tets(const State& state) {
  std::vector<int> tets;
  for (const auto& [key, lambda] : state.warm_start)
    if (row_key_kind(key) == RowKind::Strain && lambda > 0) tets.push_back(static_cast<int>(row_key_first(key)));
  std::sort(tets.begin(), tets.end());
  return static_cast<int>(std::unique(tets.begin(), tets.end()) - tets.begin());
}

// One run: a fresh World, `warmup` untimed steps, then `steps` timed ones appended to
// `samples` (and their constrained tets to `tets`). Returns the end state's hash.
uint64_t run_once(const BenchScene& bench, const SceneDesc& scene, int warmup, int steps,
                  std::vector<FrameStats>& samples, std::vector<double>& tets, const Model** model_out,
                  std::unique_ptr<World>& world) {
  world.reset();  // one World at a time (block10k's system and factor are large)
  world = std::make_unique<World>(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  for (int i = 0; i < warmup + bench.settle; ++i) world->step();
  for (int i = 0; i < steps; ++i) {
    samples.push_back(simulate_frame(*world, 1));
    tets.push_back(constrained_tets(world->state()));
  }
  *model_out = &world->model();
  return world->state_hash();
}

// Solver settings given on the command line for every scene (empty, 0 or -1: the scene's).
struct SolverOverrides {
  std::string linear, sqp_acceleration, sqp_restoration, sqp_kkt_stop, pgs_sweeps, stale_factor_precision, pair_cuts;
  int delassus_reuse = 0, pgs_subspace = -1;
  double hessian_reuse_tolerance = -1;
};

nlohmann::json bench_scene(const BenchScene& bench, int warmup, int steps, int repeat, const SolverOverrides& set) {
  SceneDesc scene = bench.make();
  if (!set.sqp_acceleration.empty()) scene.solver.sqp_acceleration = set.sqp_acceleration;
  if (!set.sqp_restoration.empty()) scene.solver.sqp_restoration = set.sqp_restoration;
  if (!set.sqp_kkt_stop.empty()) scene.solver.sqp_kkt_stop = set.sqp_kkt_stop;
  if (!set.stale_factor_precision.empty()) scene.solver.stale_factor_precision = set.stale_factor_precision;
  if (!set.linear.empty()) scene.solver.linear = set.linear;
  if (!set.pgs_sweeps.empty()) scene.solver.pgs_sweeps = set.pgs_sweeps;
  if (set.delassus_reuse > 0) scene.solver.delassus_reuse = set.delassus_reuse;
  if (set.pgs_subspace >= 0) scene.solver.pgs_subspace_interval = set.pgs_subspace;
  if (set.hessian_reuse_tolerance >= 0) scene.solver.hessian_reuse_tolerance = set.hessian_reuse_tolerance;
  if (!set.pair_cuts.empty())
    for (BodyDesc& body : scene.bodies) body.strain_limit.pair_cuts = set.pair_cuts;
  if (!bench.sleeping) scene.solver.sleep_steps = 0;
  // Repeats run the same steps again from the start (the simulation is deterministic: their
  // end states must agree), so that their spread shows the machine's timing noise (and the
  // first run's first-use costs: beam56 0.55 ms against 0.49-0.50 for the next two). The
  // stage figures below pool every repeat's timed steps. Medians are nearest-rank: of an
  // even count of runs, the lower of the middle two.
  std::vector<FrameStats> samples;
  std::vector<double> tets, repeat_medians;
  std::unique_ptr<World> world;
  const Model* model = nullptr;
  uint64_t first_hash = 0;
  bool identical = true;
  for (int r = 0; r < repeat; ++r) {
    const std::size_t begin = samples.size();
    const uint64_t hash = run_once(bench, scene, warmup, steps, samples, tets, &model, world);
    if (r == 0) first_hash = hash;
    identical = identical && hash == first_hash;
    std::vector<double> times;
    for (std::size_t i = begin; i < samples.size(); ++i) times.push_back(samples[i].step_ms);
    repeat_medians.push_back(quantile(times, 0.5));
    if (repeat > 1) std::fprintf(stderr, "  %s: repeat %d/%d, median step %.4f ms\n", bench.name.c_str(), r + 1, repeat, repeat_medians.back());
  }
  nlohmann::json stages = nlohmann::json::object();
  std::printf("%-32s %6d elements %7d dofs\n", bench.name.c_str(), model->num_elements, 3 * model->num_free);
  for (const StageSummary& s : summarize_stages(samples)) {
    stages[s.name] = {{"median_ms", s.median}, {"p95_ms", s.p95}, {"max_ms", s.max}};
    std::printf("  %-12s median %9.4f ms   p95 %9.4f ms   max %9.4f ms\n", s.name.c_str(), s.median,
                s.p95, s.max);
  }
  const std::vector<double> rows = bench::row_totals(samples), sqp = bench::iteration_counts(samples, "sqp");
  std::printf("  constraint rows median %.0f max %.0f, SQP iterations median %.0f", quantile(rows, 0.5),
              quantile(rows, 1.0), quantile(sqp, 0.5));
  if (quantile(tets, 1.0) > 0) std::printf(", constrained tets median %.0f", quantile(tets, 0.5));
  // The end state's hash: an optimisation meant to leave results alone must leave it alone.
  char hash_text[17];
  std::snprintf(hash_text, sizeof hash_text, "%016llx", static_cast<unsigned long long>(first_hash));
  std::printf(", end state %s\n", hash_text);
  if (repeat > 1) {
    std::printf("  step median of each of %d repeats:", repeat);
    for (const double m : repeat_medians) std::printf(" %.4f", m);
    std::printf(" ms; their median %.4f ms%s\n", quantile(repeat_medians, 0.5),
                identical ? ", every repeat ended in the same state" : "; WARNING: the repeats ended in different states");
  }
  // Throughput over the timed steps (their sum, not the median: slow steps count), and the
  // simulated time per wall-clock second it gives.
  double total_ms = 0;
  nlohmann::json worst = nlohmann::json::object();
  for (const FrameStats& sample : samples) {
    total_ms += sample.step_ms;
    for (const auto& [kind, value] : sample.violation) {
      if (worst.contains(kind) && worst[kind].is_null()) continue;  // a non-finite value stays
      worst[kind] = std::isfinite(value) ? nlohmann::json(std::max(worst.value(kind, 0.0), value)) : nlohmann::json();
    }
  }
  const double steps_per_second = total_ms > 0 ? 1000.0 * static_cast<double>(samples.size()) / total_ms : 0.0;
  std::printf("  %.1f steps/s, %.2fx real time (h = %.4g s)\n", steps_per_second, steps_per_second * scene.h, scene.h);
  return {{"steps_per_second", steps_per_second}, {"realtime_factor", steps_per_second * scene.h}, {"h", scene.h},
          {"violation_max", worst},
          {"rows_median", quantile(rows, 0.5)}, {"rows_max", quantile(rows, 1.0)},
          {"sqp_median", quantile(sqp, 0.5)}, {"constrained_tets_median", quantile(tets, 0.5)}, {"linear", scene.solver.linear}, {"delassus_reuse", scene.solver.delassus_reuse}, {"pgs_subspace_interval", scene.solver.pgs_subspace_interval}, {"pgs_sweeps", scene.solver.pgs_sweeps}, {"sqp_acceleration", scene.solver.sqp_acceleration}, {"sqp_restoration", scene.solver.sqp_restoration}, {"sqp_kkt_stop", scene.solver.sqp_kkt_stop}, {"stale_factor_precision", scene.solver.stale_factor_precision}, {"hessian_reuse_tolerance", scene.solver.hessian_reuse_tolerance}, {"pair_cuts", set.pair_cuts.empty() ? "scene's" : set.pair_cuts}, {"elements", model->num_elements}, {"dofs", 3 * model->num_free},
          {"steps", steps}, {"warmup", warmup + bench.settle}, {"finite", world->state().x.allFinite()},
          {"repeats", repeat}, {"step_median_per_repeat", repeat_medians},
          {"step_median_of_repeats", quantile(repeat_medians, 0.5)}, {"repeats_identical", identical}, {"end_state_hash", hash_text},
          {"sleeping", bench.sleeping},
          {"stages", stages}};
}

void print_usage(std::FILE* to) {
  std::fprintf(to,
               "usage: sinew_bench [--scene NAME | --scene-file FILE [--scene-file FILE]... | --paper-scenes]\n"
               "                   [--steps N] [--warmup N] [--threads T] [--linear cholmod|pcg] [--delassus-reuse N]\n"
               "                   [--pgs-subspace N] [--pgs-sweeps active_set|all_rows]\n"
               "                   [--sqp-acceleration conjugate|none] [--sqp-restoration accept|none] [--sqp-kkt-stop on|off]\n"
               "                   [--stale-factor-precision single|double]\n"
               "                   [--hessian-reuse-tolerance T] [--pair-cuts on|off] [--repeat N]\n"
               "                   [--cpu-placement fastest|none] [--out FILE]\n"
               "Times each scene's steps after N warm-up steps (bodies never sleep, except in rest3boxes_asleep):\n"
               "per-stage median, p95 and max, steps per second and the multiple of real time, rows, SQP\n"
               "iterations; with more than one scene, a summary table at the end.\n"
               "  --scene NAME          one built-in scene: beam56, armadillo365 (needs ../shared/meshes), block10k,\n"
               "                        creature365, beam240tet, finger324, finger324flat, rest3boxes_awake,\n"
               "                        rest3boxes_asleep (default: all of them)\n"
               "  --scene-file FILE     a scene file instead (repeatable; file names must differ), named after it\n"
               "  --paper-scenes        every assets/scenes/paper*.json of the source tree\n"
               "  --steps N             timed steps per scene (default 100)\n"
               "  --warmup N            untimed steps first (default 10)\n"
               "  --threads T           worker threads (default: all cores)\n"
               "  --linear L            solver.linear for every scene\n"
               "  --delassus-reuse N    solver.delassus_reuse for every scene\n"
               "  --pgs-subspace N      solver.pgs_subspace_interval for every scene (0: plain PGS)\n"
               "  --pgs-sweeps S        solver.pgs_sweeps for every scene (all_rows: PGS over every row on T)\n"
               "  --sqp-acceleration A  solver.sqp_acceleration for every scene (none: the SQP's plain steps)\n"
               "  --sqp-restoration R   solver.sqp_restoration for every scene (accept: a first line-search trial\n"
               "                        that brings a violated iterate within every tolerance is taken)\n"
               "  --sqp-kkt-stop S      solver.sqp_kkt_stop for every scene (off: a QP confirms every iterate)\n"
               "  --stale-factor-precision P\n"
               "                        solver.stale_factor_precision for every scene (double: solves with an\n"
               "                        earlier step's factorisation read its values in double)\n"
               "  --hessian-reuse-tolerance T\n"
               "                        solver.hessian_reuse_tolerance for every scene (hyperelastic tets keep\n"
               "                        their projected Hessian while F moves by at most T; 0: formed every time)\n"
               "  --pair-cuts on|off    strain_limit.pair_cuts of every strain-limited body (off: no cut rows where\n"
               "                        two principal stretches nearly meet, the paper's rows alone)\n"
               "  --repeat N            run each scene N times from the start (default 1): the stage figures\n"
               "                        pool every run's timed steps, and each run's median step, the median of\n"
               "                        those and whether every run ended in the same state are reported too\n"
               "                        (if not, exit code 3 once the JSON is written: a determinism bug)\n"
               "  --cpu-placement P     none (default): threads left to the scheduler; fastest: when one CPU is\n"
               "                        more than 10 %% faster than the slowest, the main thread (the step's\n"
               "                        serial stages) pinned to it and the worker threads to the others.\n"
               "                        Either way each CPU's time for a probe kernel (none with one CPU or\n"
               "                        more than 16) is taken before each\n"
               "                        scene (on shared machines the faster CPU changes within seconds) and\n"
               "                        written, with the placement, in that scene's JSON\n"
               "  --out FILE            JSON results (default bench_results.json), written once every scene ran\n");
}

// A bad command line: the message, and exit code 2 (thrown so that nothing is written).
using cli::UsageError;

// An integer option's value in [min, 10^7].
int integer_option(const std::string& option, const std::string& text, int min) {
  std::size_t used = 0;
  long value = 0;
  try {
    value = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  constexpr long kMax = 10'000'000;
  if (used == 0 || used != text.size() || value < min || value > kMax)
    throw UsageError(option + " expects an integer from " + std::to_string(min) + " to " + std::to_string(kMax) +
                     ", got '" + text + "'");
  return static_cast<int>(value);
}

struct Options {
  std::string out = "bench_results.json", only, cpu_placement = "none";
  std::vector<std::string> files;
  bool paper_scenes = false, help = false;
  int steps = 100, warmup = 10, threads = 0, repeat = 1;
  SolverOverrides set;
};

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    // An option's value: present, not empty and not the next option.
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc || argv[i + 1][0] == '\0' || std::string(argv[i + 1]).rfind("--", 0) == 0)
        throw UsageError(arg + " expects a value");
      return argv[++i];
    };
    const auto one_of = [&](const std::string& value, std::initializer_list<const char*> allowed) {
      for (const char* a : allowed)
        if (value == a) return value;
      throw UsageError(arg + " does not take '" + value + "'");
    };
    if (arg == "--out") o.out = next();
    else if (arg == "--steps") o.steps = integer_option(arg, next(), 1);
    else if (arg == "--warmup") o.warmup = integer_option(arg, next(), 0);
    else if (arg == "--repeat") o.repeat = integer_option(arg, next(), 1);
    else if (arg == "--threads") o.threads = integer_option(arg, next(), 1);
    else if (arg == "--scene") o.only = next();
    else if (arg == "--scene-file") o.files.push_back(next());
    else if (arg == "--paper-scenes") o.paper_scenes = true;
    else if (arg == "--linear") o.set.linear = one_of(next(), {"cholmod", "pcg"});
    else if (arg == "--delassus-reuse") o.set.delassus_reuse = integer_option(arg, next(), 1);
    else if (arg == "--pgs-subspace") o.set.pgs_subspace = integer_option(arg, next(), 0);
    else if (arg == "--pgs-sweeps") o.set.pgs_sweeps = one_of(next(), {"active_set", "all_rows"});
    else if (arg == "--sqp-acceleration") o.set.sqp_acceleration = one_of(next(), {"conjugate", "none"});
    else if (arg == "--sqp-restoration") o.set.sqp_restoration = one_of(next(), {"accept", "none"});
    else if (arg == "--sqp-kkt-stop") o.set.sqp_kkt_stop = one_of(next(), {"on", "off"});
    else if (arg == "--stale-factor-precision") o.set.stale_factor_precision = one_of(next(), {"single", "double"});
    else if (arg == "--pair-cuts") o.set.pair_cuts = one_of(next(), {"on", "off"});
    else if (arg == "--hessian-reuse-tolerance") o.set.hessian_reuse_tolerance = cli::parse_nonnegative(next(), arg);
    else if (arg == "--cpu-placement") o.cpu_placement = one_of(next(), {"fastest", "none"});
    else if (arg == "--help" || arg == "-h") o.help = true;
    else throw UsageError("unknown option '" + arg + "' (see --help)");
  }
  if (!o.only.empty() + !o.files.empty() + o.paper_scenes > 1)
    throw UsageError("give one of --scene, --scene-file and --paper-scenes");
  return o;
}

// The scenes to time, every file loaded; names must differ (they key the JSON).
std::vector<BenchScene> select_scenes(const Options& o) {
  std::vector<BenchScene> scenes;
  const std::vector<std::string> files = o.paper_scenes ? paper_scene_files() : o.files;
  for (const std::string& file : files) {
    scenes.push_back(file_scene(file));
    for (std::size_t k = 0; k + 1 < scenes.size(); ++k)
      if (scenes[k].name == scenes.back().name)
        throw UsageError("two scene files named " + scenes.back().name + ": " + files[k] + " and " + file);
  }
  if (!o.paper_scenes && files.empty()) {
    for (const BenchScene& bench : all_scenes())
      if (o.only.empty() || bench.name == o.only) scenes.push_back(bench);
    if (scenes.empty()) throw UsageError("no built-in scene '" + o.only + "' (see --help)");
  }
  return scenes;
}

void print_summary(const std::vector<BenchScene>& scenes, const nlohmann::json& results) {
  std::printf("\n%-36s %8s %11s %11s %10s %9s\n", "scene", "elements", "median ms", "p95 ms", "steps/s", "x real");
  for (const BenchScene& bench : scenes) {
    const nlohmann::json& r = results["scenes"][bench.name];
    if (r.contains("skipped")) {
      std::printf("%-36s skipped\n", bench.name.c_str());
      continue;
    }
    const nlohmann::json& step = r["stages"]["step"];
    std::printf("%-36s %8d %11.3f %11.3f %10.1f %9.2f\n", bench.name.c_str(), r["elements"].get<int>(),
                step["median_ms"].get<double>(), step["p95_ms"].get<double>(), r["steps_per_second"].get<double>(),
                r["realtime_factor"].get<double>());
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<BenchScene> scenes;
  try {
    o = parse_options(argc, argv);
    if (o.help) {
      print_usage(stdout);
      return 0;
    }
    scenes = select_scenes(o);
  } catch (const std::exception& e) {  // UsageError, or a scene file that does not load
    std::fprintf(stderr, "sinew_bench: %s\n", e.what());
    return 2;
  }

  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, o.threads);
  nlohmann::json results = {{"threads", o.threads > 0 ? o.threads : bench::processor_count()},
                            {"cpu", bench::cpu_model()}, {"date", bench::utc_now()},
                            {"scenes", nlohmann::json::object()}};
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const BenchScene& bench = scenes[k];
    if (scenes.size() > 1) std::fprintf(stderr, "[%zu/%zu] %s\n", k + 1, scenes.size(), bench.name.c_str());
    // Probed (and placed) afresh for each scene: which CPU is the faster one changes within seconds.
    const CpuPlacement placement = place_main_thread(o.cpu_placement);
    std::printf("%s: %s\n", bench.name.c_str(), placement.summary.c_str());
    try {
      results["scenes"][bench.name] =
          bench_scene(bench, o.warmup, o.steps, o.repeat, o.set);
      results["scenes"][bench.name]["cpu_placement"] = bench::cpu_placement_json(o.cpu_placement, placement);
    } catch (const std::exception& e) {
      std::printf("%-32s skipped: %s\n", bench.name.c_str(), e.what());
      results["scenes"][bench.name] = {{"skipped", e.what()}};
    }
  }
  if (scenes.size() > 1) print_summary(scenes, results);
  write_file_atomically(o.out, [&](std::ostream& s) { s << results.dump(2) << "\n"; });
  std::printf("wrote %s\n", o.out.c_str());
  // Repeats that ended in different states: the simulation was not deterministic, a bug.
  int status = 0;
  for (const auto& [name, r] : results["scenes"].items())
    if (r.value("repeats_identical", true) == false) {
      std::fprintf(stderr, "sinew_bench: %s: the repeats ended in different states\n", name.c_str());
      status = 3;
    }
  return status;
}
