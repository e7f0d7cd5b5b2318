#pragma once
// One ffmpeg process that encodes raw RGB frames from its stdin into an H.264 MP4:
//   ffmpeg -f rawvideo -pix_fmt rgb24 -s WxH -r FPS -i - -c:v libx264 -pix_fmt yuv420p OUT
// The video goes to a temporary file beside OUT and is renamed over OUT only when ffmpeg
// exits cleanly, so a failed or abandoned recording leaves no half-written video.
#include <cstdint>
#include <string>
#include <sys/types.h>

namespace sinew {

// Full path of the executable `name` found along $PATH (as a shell would), or "".
std::string find_in_path(const std::string& name);
// The ffmpeg executable; throws RenderError saying it is missing and how to install it.
std::string require_ffmpeg();

struct VideoFormat {
  int width = 0, height = 0;  // even: yuv420p halves the chroma planes
  double fps = 30;
};

class FfmpegEncoder {
 public:
  // Starts ffmpeg (`ffmpeg`: path of the executable). Throws RenderError if the size is odd,
  // the output's folder does not exist, or ffmpeg cannot be started.
  FfmpegEncoder(const VideoFormat& format, const std::string& ffmpeg, const std::string& output);
  // Without finish(): stops ffmpeg and removes the temporary file.
  ~FfmpegEncoder();
  FfmpegEncoder(const FfmpegEncoder&) = delete;
  FfmpegEncoder& operator=(const FfmpegEncoder&) = delete;

  // One frame, 3 * width * height bytes, top row first. Throws RenderError (with ffmpeg's
  // messages) if ffmpeg has stopped reading.
  void write_frame(const uint8_t* rgb);
  // Ends the stream, waits for ffmpeg, renames the video into place. Throws RenderError
  // with ffmpeg's messages if it failed (the temporary file is removed).
  void finish();

  const std::string& temporary_path() const { return m_temp; }

 private:
  VideoFormat m_format;
  std::string m_output, m_temp, m_log;
  pid_t m_pid = -1;
  int m_stdin = -1;
  void stop(bool kill_first);  // closes stdin and reaps ffmpeg; returns with m_pid == -1
  int m_status = 0;            // waitpid status once stopped
  std::string log_tail() const;
};

}  // namespace sinew
