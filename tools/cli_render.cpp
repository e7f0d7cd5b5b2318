#include "tools/cli_render.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "render/ffmpeg_encoder.hpp"
#include "render/renderer.hpp"
#include "render/video_recorder.hpp"

namespace sinew::cli {
namespace {

int parse_int(const std::string& text, const std::string& what) {
  int value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size()) throw UsageError(what + ": '" + text + "' is not an integer");
  return value;
}

std::pair<int, int> parse_size(const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw UsageError("option --size expects WxH (e.g. 1280x720), got '" + text + "'");
  const int w = parse_int(text.substr(0, x), "option --size"), h = parse_int(text.substr(x + 1), "option --size");
  if (w < 16 || h < 16 || w > 8192 || h > 8192)
    throw UsageError("option --size: each side must be 16..8192 pixels, got '" + text + "'");
  return {w, h};
}

std::vector<std::pair<int, std::string>> parse_screenshots(const std::string& text) {
  std::vector<std::pair<int, std::string>> shots;
  size_t begin = 0;
  while (begin <= text.size()) {
    const size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    const auto colon = item.find(':');
    if (colon == std::string::npos || colon + 1 == item.size())
      throw UsageError("option --screenshot expects FRAME:OUT.png, got '" + item + "'");
    const int frame = parse_int(item.substr(0, colon), "option --screenshot");
    if (frame < 0) throw UsageError("option --screenshot: frame must be >= 0, got '" + item + "'");
    shots.emplace_back(frame, item.substr(colon + 1));
    begin = end + 1;
  }
  return shots;
}

}  // namespace

std::vector<OptionSpec> render_option_specs() {
  return {{"--record", "OUT.mp4", "write a video of the run (H.264 through the ffmpeg program, which\n"
                                  "                          must be in PATH); frame 0 is the initial state"},
          {"--fps", "F", "video frame rate (default: the scene's fps); the video plays in real\n"
                         "                          time, so frames are dropped or repeated to match"},
          {"--size", "WxH", "picture size in pixels (default 1280x720; even for --record)"},
          {"--screenshot", "FRAME:OUT.png", "write frame FRAME (0 = initial state) as a PNG; several as\n"
                                            "                          F1:A.png,F2:B.png"},
          {"--wireframe", "", "draw the simulation lattice over the surfaces"},
          {"--color-map", "MAP", "colour the surfaces per element: energy (Ue/Umax), volume (det F),\n"
                                 "                          or none (default), with a legend"}};
}

RenderRequest parse_render_request(const Options& opts) {
  RenderRequest r;
  r.record = opts.get("--record");
  if (opts.has("--record") && r.record.empty()) throw UsageError("option --record expects a file name");
  r.fps = opts.get_double("--fps", 0, 0);
  if (opts.has("--size")) std::tie(r.width, r.height) = parse_size(opts.get("--size"));
  if (!r.record.empty() && (r.width % 2 || r.height % 2))
    throw UsageError("option --size: a video needs an even width and height (H.264 yuv420p), got " +
                     opts.get("--size"));
  if (opts.has("--screenshot")) r.screenshots = parse_screenshots(opts.get("--screenshot"));
  r.wireframe = opts.has("--wireframe");
  try {
    r.color_map = parse_color_map(opts.get("--color-map", "none"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("option --color-map: ") + e.what());
  }
  return r;
}

long video_frames_until(int frame, double scene_fps, double video_fps) {
  // Video frame k shows time k / video_fps; the tolerance absorbs rounding of equal rates.
  return long(std::floor(frame * video_fps / scene_fps + 1e-9)) + 1;
}

CliRenderer::CliRenderer(const RenderRequest& request, bool quiet) : m_request(request), m_quiet(quiet) {
  if (!request.record.empty()) m_ffmpeg = require_ffmpeg();
  RenderOptions options;
  options.width = request.width, options.height = request.height;
  options.wireframe = request.wireframe;
  options.color_map = request.color_map;
  m_renderer = std::make_unique<Renderer>(options);
}

CliRenderer::~CliRenderer() = default;

void CliRenderer::start(const Model& model, double scene_fps, int frames,
                        const std::function<void(const std::string&)>& warn) {
  for (const auto& [frame, path] : m_request.screenshots)
    if (frame > frames)
      throw UsageError("option --screenshot: frame " + std::to_string(frame) + " is after the last frame (" +
                       std::to_string(frames) + ")");
  if (m_request.color_map == ColorMapKind::Energy) {
    bool limited = false;
    for (double u : model.element_Umax) limited |= u > 0;
    if (!limited) warn("--color-map energy: no body has an energy limit, so Ue/Umax is 0 everywhere");
  }
  m_scene_fps = scene_fps;
  m_video_fps = m_request.fps > 0 ? m_request.fps : scene_fps;
  if (!m_quiet)
    std::printf("render: %dx%d, %s\n", m_request.width, m_request.height, m_renderer->description().c_str());
  if (m_request.record.empty()) return;
  VideoSettings settings;
  settings.path = m_request.record;
  settings.format = {m_request.width, m_request.height, m_video_fps};
  settings.ffmpeg = m_ffmpeg;
  m_video = std::make_unique<VideoRecorder>(settings);
}

void CliRenderer::frame(const World& world, int frame) {
  const long due = m_video ? video_frames_until(frame, m_scene_fps, m_video_fps) - m_video->frames() : 0;
  bool shot = false;
  for (const auto& s : m_request.screenshots) shot |= s.first == frame;
  if (due <= 0 && !shot) return;
  m_renderer->draw(world);
  for (long k = 0; k < due; ++k) m_video->add_frame([&](uint8_t* rgb) { m_renderer->read_rgb(rgb); });
  if (!shot) return;
  const Image image = m_renderer->image();
  for (const auto& [f, path] : m_request.screenshots)
    if (f == frame) write_png(path, image);
}

void CliRenderer::finish() {
  if (!m_video) return;
  m_video->finish();
  if (!m_quiet)
    std::printf("video: %s (%ld frames, %dx%d at %g fps)\n", m_request.record.c_str(), m_video->frames(),
                m_request.width, m_request.height, m_video_fps);
}

}  // namespace sinew::cli
