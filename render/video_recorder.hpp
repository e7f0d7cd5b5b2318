#pragma once
// Records frames into an MP4 through ffmpeg. With the capture thread (the default), the
// caller only copies a frame into a small ring (FrameRing, 3 slots); a thread flips the rows
// and feeds ffmpeg, so encoding overlaps the simulation. Without it, every frame is flipped
// and written before add_frame() returns (kept to measure what the thread saves).
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "render/ffmpeg_encoder.hpp"
#include "render/frame_ring.hpp"

namespace sinew {

struct VideoSettings {
  std::string path;              // the .mp4 to write
  VideoFormat format;
  std::string ffmpeg;            // executable; "" looks it up in PATH (RenderError if missing)
  bool capture_thread = true;
  int ring_slots = 3;            // enough to absorb one slow encode without stalling the caller
};

class VideoRecorder {
 public:
  explicit VideoRecorder(const VideoSettings& settings);
  // Without finish(): abandons the video (no file is left).
  ~VideoRecorder();
  VideoRecorder(const VideoRecorder&) = delete;
  VideoRecorder& operator=(const VideoRecorder&) = delete;

  // Adds one frame: `fill` writes 3 * width * height bytes of RGB, bottom row first (as
  // glReadPixels does). Throws RenderError if encoding has failed.
  void add_frame(const std::function<void(uint8_t*)>& fill);
  // Encodes what is queued and puts the file in place; throws RenderError on failure.
  void finish();
  long frames() const { return m_frames; }

 private:
  VideoSettings m_settings;
  std::unique_ptr<FfmpegEncoder> m_encoder;
  std::unique_ptr<FrameRing> m_ring;
  std::thread m_thread;
  std::exception_ptr m_error;   // set by the capture thread, rethrown by the caller's next call
  std::vector<uint8_t> m_gl_rows, m_rows;  // without the thread: the frame as read, and flipped
  long m_frames = 0;
  void consume();
  void join();
};

}  // namespace sinew
