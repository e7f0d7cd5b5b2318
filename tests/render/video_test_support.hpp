#pragma once
// Reading videos back in tests: ffprobe for the frame count and size, ffmpeg for pixels.
#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace sinew::test {

struct VideoInfo {
  long frames = -1;
  int width = 0, height = 0;
  std::string codec, pix_fmt, raw;  // raw: ffprobe's answer, for messages
};

inline std::string capture_output(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) out.append(buffer.data(), n);
  pclose(pipe);
  return out;
}

// Decodes every frame (-count_frames) rather than trusting the container's header.
inline VideoInfo probe_video(const std::string& path) {
  VideoInfo info;
  info.raw = capture_output("ffprobe -v error -select_streams v:0 -count_frames -show_entries "
                            "stream=codec_name,pix_fmt,width,height,nb_read_frames -of default=noprint_wrappers=1 '" +
                            path + "' 2>&1");
  size_t pos = 0;
  while (pos < info.raw.size()) {
    const size_t end = info.raw.find('\n', pos);
    const std::string line = info.raw.substr(pos, end - pos);
    pos = end == std::string::npos ? info.raw.size() : end + 1;
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "nb_read_frames") info.frames = std::stol(value);
    if (key == "width") info.width = std::stoi(value);
    if (key == "height") info.height = std::stoi(value);
    if (key == "codec_name") info.codec = value;
    if (key == "pix_fmt") info.pix_fmt = value;
  }
  return info;
}

// The first frame as RGB, top row first.
inline std::vector<uint8_t> first_frame_rgb(const std::string& path) {
  const std::string raw =
      capture_output("ffmpeg -v error -i '" + path + "' -frames:v 1 -f rawvideo -pix_fmt rgb24 - 2>/dev/null");
  return std::vector<uint8_t>(raw.begin(), raw.end());
}

}  // namespace sinew::test
