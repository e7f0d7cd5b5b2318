// sinew_bench_realtime: a scene in the fixed-budget real-time loop against the same scene at
// its own caps (the reference, deterministic): frame times, frames over budget, the worst
// constraint violations of both, and how far the budgeted run's surfaces end up from the
// reference's, frame by frame. Issue 7, section 5: "a 10k-hex body with energy limits and
// contact holding 60 Hz in the real-time loop, with its error against a converged reference
// reported next to it". By default the scale sweep's resting block (energy limit, ground
// contact; tools/scale_sweep/lattice_scene.hpp) at ~10,000 cells.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/model.hpp"
#include "engine/core/error.hpp"
#include "engine/core/progress.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/realtime/realtime_loop.hpp"
#include "engine/scene/scene.hpp"
#include "engine/world.hpp"
#include "tools/cli_options.hpp"
#include "tools/scale_sweep/lattice_scene.hpp"

using namespace sinew;

namespace {

// One run: per frame its time and stats, and the bodies' surfaces after it.
struct Run {
  std::vector<double> frame_ms;
  std::vector<FrameStats> stats;
  std::vector<std::vector<std::vector<Vec3>>> surfaces;  // per frame, per body
  int over_budget = 0;
  bool finite = true;
};

Run run(const SceneDesc& scene, const Model& model, int frames, double budget_ms, const std::string& label) {
  World world(Model(model), initial_velocities(scene));
  RealtimeSettings settings;
  settings.budget_ms = budget_ms;
  settings.fps = scene.fps;
  RealtimeLoop loop(scene.solver, settings);
  Run r;
  Progress progress(label, frames);
  for (int f = 1; f <= frames && r.finite; ++f) {
    const auto start = std::chrono::steady_clock::now();
    r.stats.push_back(loop.frame(world, scene.steps_per_frame()));
    r.frame_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    r.finite = r.stats.back().finite;
    r.surfaces.push_back(world.state().surface);
    progress.update(f);
  }
  progress.finish();
  r.over_budget = loop.counters().over_budget;
  return r;
}

// The worst value of each violation kind over the frames.
std::map<std::string, double> worst_violations(const Run& r) {
  std::map<std::string, double> worst;
  for (const FrameStats& s : r.stats)
    for (const auto& [kind, value] : s.violation)
      if (std::isfinite(value)) worst[kind] = worst.count(kind) ? std::max(worst[kind], value) : value;
  return worst;
}

nlohmann::json run_json(const Run& r, double budget_ms) {
  nlohmann::json j = {{"frames", r.frame_ms.size()},
                      {"frame_ms_median", quantile(r.frame_ms, 0.5)},
                      {"frame_ms_p95", quantile(r.frame_ms, 0.95)},
                      {"frame_ms_max", quantile(r.frame_ms, 1.0)},
                      {"finite", r.finite},
                      {"worst_violation", worst_violations(r)}};
  int sqp = 0, pgs = 0;
  for (const FrameStats& s : r.stats) {
    if (const auto it = s.iterations.find("sqp"); it != s.iterations.end()) sqp += it->second;
    if (const auto it = s.iterations.find("pgs"); it != s.iterations.end()) pgs += it->second;
  }
  j["sqp_iterations"] = sqp;
  j["pgs_sweeps"] = pgs;
  if (budget_ms > 0) {
    j["budget_ms"] = budget_ms;
    j["over_budget_frames"] = r.over_budget;
  }
  return j;
}

// RMS and largest distance between two runs' surface vertices after one frame.
std::pair<double, double> surface_distance(const std::vector<std::vector<Vec3>>& a,
                                           const std::vector<std::vector<Vec3>>& b) {
  double sum = 0, largest = 0;
  long count = 0;
  for (size_t body = 0; body < a.size() && body < b.size(); ++body)
    for (size_t v = 0; v < a[body].size() && v < b[body].size(); ++v) {
      const double d = (a[body][v] - b[body][v]).norm();
      sum += d * d, largest = std::max(largest, d), ++count;
    }
  return {count ? std::sqrt(sum / count) : 0.0, largest};
}

}  // namespace

int main(int argc, char** argv) {
  cli::Options options(
      "sinew_bench_realtime [--size N | --scene-file FILE] [--frames N] [--budget MS] [--threads T] [--out FILE]",
      "A scene in the fixed-budget real-time loop (sinew run --budget) against the same scene at\n"
      "its own caps (the reference): frame times (median, p95, max; nearest rank, so with fewer\n"
      "than 20 frames p95 is the max), frames over budget, the worst\n"
      "violation of each kind in both runs, and the RMS and largest distance between their surface\n"
      "vertices after every frame. Default: the scale sweep's resting block (energy limit, ground\n"
      "contact) at ~10,000 cells. Progress on stderr; exit code 3 if a run stopped non-finite.",
      {{"--size", "N", "the scale sweep's block nearest N cells (default 10000)"},
       {"--scene-file", "FILE", "a scene file instead of the block"},
       {"--frames", "N", "frames to run, from the start (default 10)"},
       {"--budget", "MS", "simulation budget per frame in ms (default 16.667, 60 Hz)"},
       {"--threads", "T", "worker threads (default 2)"},
       {"--out", "FILE", "JSON results (default bench_realtime.json)"}},
      0);
  int size = 10000, frames = 10, threads = 2;
  double budget = 1000.0 / 60;
  std::string out = "bench_realtime.json";
  SceneDesc scene;
  Model model;
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    size = options.get_int("--size", size, 1);
    frames = options.get_int("--frames", frames, 1);
    threads = options.get_int("--threads", threads, 1);
    budget = options.get_double("--budget", budget, 0);
    out = options.get("--out", out);
    if (options.has("--scene-file") && options.has("--size"))
      throw cli::UsageError("--size '" + options.get("--size", "") + "' and --scene-file '" +
                            options.get("--scene-file", "") + "' exclude each other");
    if (const std::filesystem::path folder = std::filesystem::path(out).parent_path();
        !folder.empty() && !std::filesystem::is_directory(folder))
      throw cli::UsageError("--out '" + out + "': no folder " + folder.string());
    if (options.has("--scene-file")) {
      const std::string path = options.get("--scene-file", "");
      try {
        scene = load_scene(path);
        model = build_model(scene, [](const std::string& warning) { std::fprintf(stderr, "warning: %s\n", warning.c_str()); });
      } catch (const InputError& e) {
        throw cli::UsageError("--scene-file '" + path + "': " + e.what());
      }
    } else {
      const sweep::RestingBlock block;
      scene = parse_scene_text(sweep::lattice_scene_text(sweep::lattice_for(size, block), block), "block",
                               SINEW_SOURCE_DIR);
      model = build_model(scene, [](const std::string&) {});
    }
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_realtime: %s\n", e.what());
    return 2;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  // The reference first: it also pays the first steps' costs (thread pool, buffers), which
  // only makes the budget's comparison conservative.
  const Run reference = run(scene, model, frames, 0, "reference");
  const Run budgeted = run(scene, model, frames, budget, "budgeted");
  nlohmann::json distance = nlohmann::json::array();
  // Frames both runs completed: after a refused step the surfaces are not the state's.
  const auto completed = [](const Run& r) { return r.finite ? r.surfaces.size() : r.surfaces.size() - 1; };
  const size_t common = std::min(completed(reference), completed(budgeted));
  double rms_end = 0, max_end = 0;
  for (size_t f = 0; f < common; ++f) {
    std::tie(rms_end, max_end) = surface_distance(reference.surfaces[f], budgeted.surfaces[f]);
    distance.push_back({{"frame", f + 1}, {"rms_m", rms_end}, {"max_m", max_end}});
  }
  const nlohmann::json result = {{"scene", scene.name},
                                 {"frames", frames},
                                 {"threads", threads},
                                 {"budget_ms", budget},
                                 {"reference", run_json(reference, 0)},
                                 {"budgeted", run_json(budgeted, budget)},
                                 {"frames_compared", common},
                                 {"surface_distance", distance}};
  try {
    write_file_atomically(out, [&](std::ostream& os) { os << result.dump(2) << "\n"; });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinew_bench_realtime: %s\n", e.what());
    return 1;
  }
  std::printf("%s, %d frames, %d threads\n", scene.name.c_str(), frames, threads);
  std::printf("  reference: frame median %.2f ms, max %.2f ms\n", quantile(reference.frame_ms, 0.5),
              quantile(reference.frame_ms, 1.0));
  std::printf("  budget %.3g ms: frame median %.2f ms, max %.2f ms, %d of %zu frames over budget\n", budget,
              quantile(budgeted.frame_ms, 0.5), quantile(budgeted.frame_ms, 1.0), budgeted.over_budget,
              budgeted.frame_ms.size());
  for (const auto& [label, r] : {std::pair<const char*, const Run*>{"reference", &reference}, {"budgeted", &budgeted}})
    for (const auto& [kind, value] : worst_violations(*r)) std::printf("  %s worst %s %.3g\n", label, kind.c_str(), value);
  std::printf("  surfaces after frame %zu: %.3g m RMS, %.3g m max apart\n", common, rms_end, max_end);
  std::printf("wrote %s\n", out.c_str());
  return reference.finite && budgeted.finite ? 0 : 3;
}
