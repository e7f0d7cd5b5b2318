#pragma once
// `sinew run`'s pictures: --record (MP4), --screenshot (PNG), and how they are drawn
// (--size, --fps, --wireframe, --color-map). Kept out of cli_run.cpp so that the run loop
// only calls start / frame / finish.
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/world.hpp"
#include "render/color_map.hpp"
#include "tools/cli_options.hpp"

namespace sinew {
class Renderer;
class VideoRecorder;
}  // namespace sinew

namespace sinew::cli {

std::vector<OptionSpec> render_option_specs();

struct RenderRequest {
  std::string record;                                   // "" = no video
  double fps = 0;                                       // 0 = the scene's fps
  int width = 1280, height = 720;
  std::vector<std::pair<int, std::string>> screenshots;  // frame, PNG path
  bool wireframe = false;
  ColorMapKind color_map = ColorMapKind::None;
  bool wanted() const { return !record.empty() || !screenshots.empty(); }
};

// Throws UsageError for malformed values (before the scene loads).
RenderRequest parse_render_request(const Options& opts);

// How many video frames at `video_fps` show times up to the end of simulated frame `frame`
// of a scene output at `scene_fps` (frame 0 is the initial state, shown by video frame 0).
long video_frames_until(int frame, double scene_fps, double video_fps);

class CliRenderer {
 public:
  // Finds ffmpeg (if recording) and creates the EGL context now, before any simulation, so a
  // missing tool fails at once. Throws RenderError.
  CliRenderer(const RenderRequest& request, bool quiet);
  ~CliRenderer();  // an unfinished video is abandoned: no file is left
  // Checks the screenshot frames against the run's length and starts the video.
  void start(const Model& model, double scene_fps, int frames, const std::function<void(const std::string&)>& warn);
  // Draws what is due after simulated frame `frame` (0 = the initial state).
  void frame(const World& world, int frame);
  // Completes the video; prints where it went unless quiet.
  void finish();

 private:
  RenderRequest m_request;
  bool m_quiet;
  std::string m_ffmpeg;
  std::unique_ptr<Renderer> m_renderer;
  std::unique_ptr<VideoRecorder> m_video;
  double m_scene_fps = 60, m_video_fps = 60;
};

}  // namespace sinew::cli
