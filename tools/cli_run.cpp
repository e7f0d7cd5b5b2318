// `sinew run`: a scene headless, with progress, exports, stats and a timing summary.
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "engine/analysis/element_fields.hpp"
#include "engine/core/cpu_placement.hpp"
#include "engine/core/error.hpp"
#include "engine/core/progress.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/mesh_export.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/realtime/realtime_loop.hpp"
#include "engine/simulate_frame.hpp"
#include "tools/cli_commands.hpp"
#include "tools/cli_options.hpp"
#include "tools/cli_render.hpp"

namespace sinew::cli {
namespace {

Options run_options() {
  std::vector<OptionSpec> specs = {
      {"--frames", "N", "frames to simulate (default: the scene's \"frames\")"},
       {"--threads", "T", "worker threads (default: all cores); results do not depend on T"},
       {"--stats", "FILE", "write per-frame statistics as JSON (frames, stages, rows, iterations,\n"
                           "                          violation, kinetic energy, finite) plus a summary"},
       {"--export-obj", "DIR", "write each body's embedded surface per frame: DIR/BODY_NNNNN.obj"},
       {"--export-vtu", "DIR", "write each body's lattice per frame with per-element fields\n"
                               "                          (energy_density, volume_ratio, energy_ratio):\n"
                               "                          DIR/BODY_NNNNN.vtu and the index DIR/BODY.pvd"},
       {"--realtime", "", "run paced to wall time, one frame per 1/fps s, with a simulation budget per\n"
                          "                          frame (default: the frame period, or --budget): iteration caps\n"
                          "                          shrink to fit it; over-budget frames are counted. Every thread\n"
                          "                          spins the last 4 ms before each frame, so that the frame's first\n"
                          "                          parallel stage finds them awake. Not deterministic"},
       {"--budget", "MS", "simulation budget per frame in ms (with or without --realtime): SQP, PGS,\n"
                          "                          Newton and PCG caps adapt to what is left of it; a step they leave\n"
                          "                          more than solver.budget_violation_limit tolerances past a constraint\n"
                          "                          is redone at the scene's caps. Not deterministic; without --budget\n"
                          "                          and --realtime the scene's caps hold"},
       {"--cpu-placement", "P", "none (default): threads left to the scheduler; fastest: when one CPU runs a\n"
                                "                          probe kernel more than 10 % faster than the slowest, the main thread\n"
                                "                          (the step's serial stages) is pinned to it and worker threads to the\n"
                                "                          others. Either way each CPU's probe time is printed and written in\n"
                                "                          the stats summary (cpu_probe_ms; none with one CPU or more than 16):\n"
                                "                          CPUs of shared virtual machines may differ in speed, by turns.\n"
                                "                          Results do not depend on it"},
       {"--quiet", "", "print nothing but errors"}};
  for (OptionSpec& s : render_option_specs()) specs.push_back(std::move(s));
  return Options("sinew run SCENE [options]",
                 "Simulates SCENE (a JSON file, see docs/scenes.md) without a window, as fast as\n"
                 "possible, and prints a per-stage timing summary (median and max per frame);\n"
                 "optionally records a video or screenshots, drawn off-screen (EGL, no display needed).",
                 std::move(specs), 1);
}

std::string frame_file(const std::string& dir, const std::string& body, int frame, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "_%05d.%s", frame, ext);
  return (std::filesystem::path(dir) / (body + name)).string();
}

// Writes the frame's OBJ and VTU exports (frame 0 is the initial state).
struct Exporter {
  std::string obj_dir, vtu_dir;
  std::vector<std::unique_ptr<PvdCollection>> pvd;

  void start(const Model& model) {
    if (!obj_dir.empty()) ensure_directory(obj_dir);
    if (vtu_dir.empty()) return;
    ensure_directory(vtu_dir);
    for (const Body& b : model.bodies) pvd.push_back(std::make_unique<PvdCollection>(vtu_dir, b.name));
  }

  void write(const World& world, int frame) {
    const Model& model = world.model();
    const State& state = world.state();
    if (!obj_dir.empty())
      for (size_t b = 0; b < model.bodies.size(); ++b) {
        TriMesh mesh{state.surface[b], model.bodies[b].rest_surface.triangles};
        write_obj(frame_file(obj_dir, model.bodies[b].name, frame, "obj"), mesh);
      }
    if (vtu_dir.empty()) return;
    const auto fields = compute_element_fields(model, state);
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const Body& body = model.bodies[b];
      std::vector<Vec3> points(body.num_nodes());
      for (int n = 0; n < body.num_nodes(); ++n) points[n] = state.x.segment<3>(3 * (body.node_offset + n));
      std::map<std::string, std::vector<double>> body_fields;
      for (const auto& [name, values] : fields)
        body_fields[name].assign(values.begin() + body.element_offset,
                                 values.begin() + body.element_offset + body.num_elements());
      const std::string file = frame_file(vtu_dir, body.name, frame, "vtu");
      write_vtu(file, points, body.lattice.cells, body_fields);
      pvd[b]->add(state.t, std::filesystem::path(file).filename().string());
    }
  }
};

void print_summary(const std::vector<FrameStats>& frames, double wall_s, double sim_s) {
  std::printf("\n%-12s %10s %10s %10s\n", "stage", "median ms", "max ms", "skipped");
  for (const StageSummary& s : summarize_stages(frames))
    std::printf("%-12s %10.3f %10.3f %10d\n", s.name.c_str(), s.median, s.max, s.frames_skipped);
  std::printf("\n%zu frames, %.3f s simulated in %.3f s wall (%.2fx real time)\n", frames.size(),
              sim_s, wall_s, wall_s > 0 ? sim_s / wall_s : 0.0);
}

nlohmann::json summary_json(const std::vector<FrameStats>& frames, const World& world, int steps_per_frame,
                            double wall_s, bool finite) {
  nlohmann::json stages = nlohmann::json::object();
  for (const StageSummary& s : summarize_stages(frames))
    stages[s.name] = {{"median_ms", s.median}, {"p95_ms", s.p95}, {"p99_ms", s.p99},
                      {"max_ms", s.max},       {"total_ms", s.total}, {"frames_skipped", s.frames_skipped}};
  const Model& m = world.model();
  return {{"scene", m.scene_name},       {"frames", frames.size()},
          {"steps_per_frame", steps_per_frame}, {"h", m.h},
          {"elements", m.num_elements},  {"nodes", m.num_nodes},
          {"dofs", 3 * m.num_free},      {"wall_s", wall_s},
          {"simulated_s", world.state().t}, {"finite", finite},
          {"state_hash", std::to_string(world.state_hash())}, {"stages", stages}};
}

}  // namespace

int run_command(int argc, char** argv) {
  Options opts = run_options();
  if (!opts.parse(argc, argv)) return 0;
  const bool quiet = opts.has("--quiet");
  auto warn = [](const std::string& text) { std::fprintf(stderr, "warning: %s\n", text.c_str()); };

  // Options first, so that a typo is reported before a long scene load.
  const int frames_option = opts.get_int("--frames", 0, 1);
  const int threads = opts.get_int("--threads", 0, 1);
  const bool realtime = opts.has("--realtime");
  std::string placement_mode = opts.get_one_of("--cpu-placement", {"none", "fastest"});
  if (placement_mode.empty()) placement_mode = "none";
  const double budget_option = opts.get_double("--budget", 0, 0);
  const RenderRequest render_request = parse_render_request(opts);
  if (!render_request.wanted() && (opts.has("--wireframe") || opts.has("--color-map") || opts.has("--size")))
    warn("--wireframe, --color-map and --size only matter with --record or --screenshot");
  // Before the scene loads: a missing ffmpeg or EGL fails at once, not after a long run.
  std::unique_ptr<CliRenderer> renderer;
  if (render_request.wanted()) renderer = std::make_unique<CliRenderer>(render_request, quiet);
  SceneDesc scene = load_scene(opts.positional()[0]);
  const int frames = frames_option > 0 ? frames_option : scene.frames;
  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

  World world(build_model(scene, warn), initial_velocities(scene));
  const Model& model = world.model();
  if (!quiet) {
    std::printf("scene '%s': %zu bodies, %d elements, %d nodes, %d free DOFs, h = %g s, %d steps/frame\n",
                model.scene_name.c_str(), model.bodies.size(), model.num_elements, model.num_nodes,
                3 * model.num_free, model.h, scene.steps_per_frame());
    for (const Body& b : model.bodies) {
      const bool tets = b.element_type == ElementType::Tet4;
      std::printf("  body '%s': %d %s of size %g m%s, %d nodes, %s, surface %zu vertices / %zu triangles\n",
                  b.name.c_str(), b.num_elements(), tets ? "tets" : "hex cells", b.lattice.cell_size,
                  "", b.num_nodes(), b.hyperelastic ? b.hyperelastic->name() : "linear corotational",
                  b.rest_surface.vertices.size(), b.rest_surface.triangles.size());
    }
  }

  Exporter exporter{opts.get("--export-obj"), opts.get("--export-vtu"), {}};
  exporter.start(model);
  exporter.write(world, 0);
  if (renderer) {
    renderer->start(model, scene.fps, frames, warn);
    renderer->frame(world, 0);
  }

  // After the renderer started its recording thread and ffmpeg (which take the CPU set of
  // the thread that starts them: pinned, they would share the main thread's one CPU).
  const CpuPlacement placement = place_main_thread(placement_mode);
  if (!quiet) std::printf("%s\n", placement.summary.c_str());

  RealtimeSettings pacing;
  pacing.paced = realtime;
  pacing.fps = scene.fps;
  pacing.budget_ms = budget_option > 0 ? budget_option : realtime ? 1000.0 / scene.fps : 0;
  RealtimeLoop loop(scene.solver, pacing);

  std::vector<FrameStats> stats;
  Progress progress("run", quiet ? 0 : frames);
  const auto start = std::chrono::steady_clock::now();
  bool finite = true;
  for (int f = 1; f <= frames && finite; ++f) {
    stats.push_back(loop.frame(world, scene.steps_per_frame()));
    finite = stats.back().finite;
    exporter.write(world, f);
    if (renderer) renderer->frame(world, f);
    progress.update(f);
  }
  progress.finish();
  if (renderer) renderer->finish();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  nlohmann::json summary = summary_json(stats, world, scene.steps_per_frame(), wall_s, finite);
  summary["cpu_placement"] = placement_mode;
  summary["cpu_pinned"] = placement.pinned_cpu;
  summary["cpu_probe_ms"] = nlohmann::json::object();
  for (const CpuTiming& t : placement.timings) summary["cpu_probe_ms"][std::to_string(t.cpu)] = t.ms;
  if (pacing.budget_ms > 0) {
    summary["budget_ms"] = pacing.budget_ms;
    summary["over_budget_frames"] = loop.counters().over_budget;
    summary["paced"] = realtime;
  }
  if (opts.has("--stats")) write_stats_json(opts.get("--stats"), stats, summary);
  if (!quiet) print_summary(stats, wall_s, world.state().t);
  if (!quiet && pacing.budget_ms > 0)
    std::printf("budget %.3g ms per frame%s: %d of %d frames over budget\n", pacing.budget_ms,
                realtime ? " (paced to wall time)" : "", loop.counters().over_budget, loop.counters().frames);
  if (!finite) {
    std::fprintf(stderr,
                 "error: the simulation met a NaN/Inf, a singular system, a node faster than solver.max_speed\n"
                 "       or a constraint more than solver.divergence_violation_limit times its tolerance past it\n"
                 "       at t = %.4f s, also when retried afresh and in 2 and 4 sub-steps, and stopped;\n"
                 "       outputs hold the last valid state (frame %zu)\n",
                 world.state().t, stats.size() - 1);
    return 3;
  }
  return 0;
}

}  // namespace sinew::cli
