// sinew_bench_render: what drawing and recording cost per frame, on whatever GL the machine
// has (llvmpipe on CPU machines). Medians over the frames of a run; JSON out.
//
// Per scene:
//   render:  draw (up to glFinish) and readback (resolve + glReadPixels) of each frame, the
//            simulation run between frames but not timed;
//   record:  a live simulation loop, timed per frame as simulate + draw + hand the frame on,
//            three ways: frames only read back into a buffer (no video), recording with the
//            capture thread, recording without it (flip + pipe write in the loop). Overhead =
//            median loop frame minus the no-video median. `finish_ms` is the wait for ffmpeg
//            to drain at the end, which the thread moves out of the loop.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <tuple>
#include <unistd.h>

#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/simulate_frame.hpp"
#include "render/renderer.hpp"
#include "render/video_recorder.hpp"
#include "tools/cli_options.hpp"

using namespace sinew;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

nlohmann::json summary(const std::vector<double>& samples) {
  return {{"median_ms", quantile(samples, 0.5)}, {"p95_ms", quantile(samples, 0.95)}, {"max_ms", quantile(samples, 1.0)}};
}

World make_world(const SceneDesc& scene) {
  return World(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
}

nlohmann::json bench_render(const SceneDesc& scene, const RenderOptions& options, int frames, int warmup) {
  World world = make_world(scene);
  Renderer renderer(options);
  std::vector<uint8_t> pixels(3 * size_t(options.width) * options.height);
  std::vector<double> draw, readback, total;
  for (int f = 0; f < warmup + frames; ++f) {
    if (f > 0) simulate_frame(world, scene.steps_per_frame());
    const auto t0 = Clock::now();
    renderer.draw(world);
    renderer.read_rgb(pixels.data());  // waits for the draw: GL is asynchronous
    const double t_total = ms_since(t0);
    if (f < warmup) continue;
    total.push_back(t_total);
  }
  // The split: draw alone is timed with a readback of a single frame after it, so that the
  // draw's queued work is included; readback alone repeats the read of the finished frame.
  for (int i = 0; i < frames; ++i) {
    auto t0 = Clock::now();
    renderer.draw(world);
    renderer.read_rgb(pixels.data());
    const double both = ms_since(t0);
    t0 = Clock::now();
    renderer.read_rgb(pixels.data());
    const double read = ms_since(t0);
    readback.push_back(read);
    draw.push_back(both - read);
  }
  return {{"draw_plus_readback", summary(total)}, {"draw_same_frame", summary(draw)},
          {"readback_only", summary(readback)}};
}

enum class Mode { NoVideo, CaptureThread, Synchronous };

nlohmann::json bench_record(const SceneDesc& scene, const RenderOptions& options, int frames, Mode mode,
                            const fs::path& video) {
  World world = make_world(scene);
  Renderer renderer(options);
  std::vector<uint8_t> pixels(3 * size_t(options.width) * options.height);
  std::unique_ptr<VideoRecorder> recorder;
  if (mode != Mode::NoVideo) {
    VideoSettings settings;
    settings.path = video.string();
    settings.format = {options.width, options.height, scene.fps};
    settings.capture_thread = mode == Mode::CaptureThread;
    recorder = std::make_unique<VideoRecorder>(settings);
  }
  std::vector<double> loop, simulate, hand_on;
  const auto run_start = Clock::now();
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    simulate_frame(world, scene.steps_per_frame());
    const auto t1 = Clock::now();
    renderer.draw(world);
    if (recorder) recorder->add_frame([&](uint8_t* rgb) { renderer.read_rgb(rgb); });
    else renderer.read_rgb(pixels.data());
    simulate.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    hand_on.push_back(ms_since(t1));
    loop.push_back(ms_since(t0));
  }
  const auto finish_start = Clock::now();
  if (recorder) recorder->finish();
  const double finish_ms = ms_since(finish_start);
  const double wall_ms = ms_since(run_start);
  fs::remove(video);
  return {{"loop_frame", summary(loop)}, {"simulate", summary(simulate)}, {"draw_and_hand_on", summary(hand_on)},
          {"finish_ms", finish_ms}, {"wall_ms_per_frame", wall_ms / frames}};
}

// "WxH": two positive integers.
std::pair<int, int> parse_size(const std::string& text) {
  const cli::UsageError error("option --size expects WxH, two integers >= 1 (e.g. 1280x720), got '" + text + "'");
  const auto x = text.find('x');
  if (x == std::string::npos) throw error;
  try {  // parse_int's own message replaced by one that shows the whole value
    return {cli::parse_int(text.substr(0, x), "width", 1), cli::parse_int(text.substr(x + 1), "height", 1)};
  } catch (const cli::UsageError&) {
    throw error;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress shows even when piped
  cli::Options args(
      "sinew_bench_render [OPTION...]",
      "What drawing and recording cost per frame on this machine's GL (llvmpipe on CPU machines):\n"
      "draw and readback, then a live loop with no video, with the capture thread and without it.\n"
      "Medians over the frames of a run; JSON out.",
      {{"--scene", "FILE", "scene, relative to the source tree or absolute\n"
                           "                          (default assets/scenes/default.json)"},
       {"--frames", "N", "timed frames per measurement (default 60)"},
       {"--warmup", "N", "untimed frames before the draw and readback timing (default 5)"},
       {"--size", "WxH", "picture size in pixels (default 1280x720)"},
       {"--samples", "S", "MSAA samples, at most what the driver offers; 0 or 1: none (default 4)"},
       {"--out", "FILE", "JSON results (default bench_render.json)"}},
      0);
  std::string out = "bench_render.json";
  std::vector<std::string> scenes = {"assets/scenes/default.json"};
  int frames = 60, warmup = 5, width = 1280, height = 720, samples = 4;
  try {
    if (!args.parse(argc - 1, argv + 1)) return 0;
    out = args.get("--out", out);
    if (args.has("--scene")) scenes = {args.get("--scene")};
    frames = args.get_int("--frames", frames, 1);
    warmup = args.get_int("--warmup", warmup, 0);
    samples = args.get_int("--samples", samples, 0);
    if (args.has("--size")) std::tie(width, height) = parse_size(args.get("--size"));
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_render: %s\n", e.what());
    return 2;
  }
  RenderOptions options;
  options.width = width, options.height = height;
  options.samples = samples;
  nlohmann::json results = {{"size", std::to_string(width) + "x" + std::to_string(height)},
                            {"frames", frames}, {"msaa_samples", samples}, {"scenes", nlohmann::json::object()}};
  const fs::path video = fs::temp_directory_path() / ("sinew_bench_render_" + std::to_string(getpid()) + ".mp4");
  try {
    {
      Renderer probe(options);
      results["renderer"] = probe.description();
      std::printf("renderer: %s, %dx%d\n", probe.description().c_str(), width, height);
    }
    for (const std::string& name : scenes) {
      const std::string path = fs::path(name).is_absolute() ? name : std::string(SINEW_SOURCE_DIR) + "/" + name;
      const SceneDesc scene = load_scene(path);
      nlohmann::json r;
      r["render"] = bench_render(scene, options, frames, warmup);
      r["record_none"] = bench_record(scene, options, frames, Mode::NoVideo, video);
      r["record_capture_thread"] = bench_record(scene, options, frames, Mode::CaptureThread, video);
      r["record_synchronous"] = bench_record(scene, options, frames, Mode::Synchronous, video);
      const double base = r["record_none"]["loop_frame"]["median_ms"];
      const double base_hand_on = r["record_none"]["draw_and_hand_on"]["median_ms"];
      // Two views of the overhead: what the loop waits for after simulating (steady, the
      // figure to quote), and the whole loop frame (also shows ffmpeg taking CPU from the
      // simulation, but carries the simulation's own run-to-run noise).
      for (const char* mode : {"record_capture_thread", "record_synchronous"}) {
        r[mode]["overhead_hand_on_median_ms"] = double(r[mode]["draw_and_hand_on"]["median_ms"]) - base_hand_on;
        r[mode]["overhead_loop_median_ms"] = double(r[mode]["loop_frame"]["median_ms"]) - base;
      }
      results["scenes"][name] = r;
      std::printf("%s\n  draw+readback median %.2f ms (draw %.2f, readback %.2f)\n", name.c_str(),
                  double(r["render"]["draw_plus_readback"]["median_ms"]),
                  double(r["render"]["draw_same_frame"]["median_ms"]),
                  double(r["render"]["readback_only"]["median_ms"]));
      for (const char* mode : {"record_none", "record_capture_thread", "record_synchronous"})
        std::printf("  %-22s loop frame median %7.2f ms (simulate %6.2f, draw+hand on %6.2f), finish %7.1f ms, "
                    "wall %7.2f ms/frame\n",
                    mode, double(r[mode]["loop_frame"]["median_ms"]), double(r[mode]["simulate"]["median_ms"]),
                    double(r[mode]["draw_and_hand_on"]["median_ms"]), double(r[mode]["finish_ms"]),
                    double(r[mode]["wall_ms_per_frame"]));
      for (const char* mode : {"record_capture_thread", "record_synchronous"})
        std::printf("  overhead %-22s %+.2f ms per frame waited for (%+.2f ms per whole loop frame)\n", mode,
                    double(r[mode]["overhead_hand_on_median_ms"]), double(r[mode]["overhead_loop_median_ms"]));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    fs::remove(video);
    return 1;
  }
  write_file_atomically(out, [&](std::ostream& s) { s << results.dump(2) << "\n"; });
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
