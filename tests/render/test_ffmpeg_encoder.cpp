// The ffmpeg process: finding it, encoding frames, and leaving no file when anything fails.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "render/ffmpeg_encoder.hpp"
#include "render/render_error.hpp"
#include "tests/render/video_test_support.hpp"

using namespace sinew;
namespace fs = std::filesystem;

namespace {

struct EncoderTempDir {
  fs::path path;
  explicit EncoderTempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("sinew_ffmpeg_" + name + "_" + std::to_string(getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~EncoderTempDir() { fs::remove_all(path); }
  size_t count() const { return size_t(std::distance(fs::directory_iterator(path), fs::directory_iterator())); }
};

std::vector<uint8_t> grey_frame(int w, int h, uint8_t level) { return std::vector<uint8_t>(3 * size_t(w) * h, level); }

}  // namespace

TEST_CASE("ffmpeg: found along PATH; a missing one gets an error that says how to install it") {
  CHECK(!find_in_path("ffmpeg").empty());
  CHECK(find_in_path("sinew-no-such-program").empty());
  const std::string saved = std::getenv("PATH");
  EncoderTempDir empty("path");
  setenv("PATH", empty.path.c_str(), 1);
  CHECK(find_in_path("ffmpeg").empty());
  CHECK_THROWS_WITH_AS(require_ffmpeg(), doctest::Contains("apt-get install ffmpeg"), RenderError);
  setenv("PATH", saved.c_str(), 1);
}

TEST_CASE("ffmpeg: 12 frames at 64x48 make an H.264 yuv420p MP4 of 12 frames at 64x48") {
  EncoderTempDir dir("ok");
  const std::string out = (dir.path / "v.mp4").string();
  FfmpegEncoder encoder({64, 48, 24}, find_in_path("ffmpeg"), out);
  for (int i = 0; i < 12; ++i) encoder.write_frame(grey_frame(64, 48, uint8_t(20 * i)).data());
  CHECK(!fs::exists(out));  // not before finish(): it is written under a temporary name
  encoder.finish();
  const test::VideoInfo info = test::probe_video(out);
  INFO(info.raw);
  CHECK(info.frames == 12);
  CHECK(info.width == 64);
  CHECK(info.height == 48);
  CHECK(info.codec == "h264");
  CHECK(info.pix_fmt == "yuv420p");
  CHECK(dir.count() == 1);  // no temporary or log file left beside it
}

TEST_CASE("ffmpeg: an abandoned recording leaves no file at all") {
  EncoderTempDir dir("abandon");
  {
    FfmpegEncoder encoder({32, 32, 30}, find_in_path("ffmpeg"), (dir.path / "v.mp4").string());
    encoder.write_frame(grey_frame(32, 32, 100).data());
  }
  CHECK(dir.count() == 0);
}

TEST_CASE("ffmpeg: a failing encoder is reported with its messages, and nothing is left") {
  EncoderTempDir dir("fail");
  // A stand-in "ffmpeg" that complains and exits without reading: the writer sees EPIPE.
  const fs::path fake = dir.path / "fake-ffmpeg";
  std::ofstream(fake) << "#!/bin/sh\necho 'codec exploded' >&2\nexit 3\n";
  fs::permissions(fake, fs::perms::owner_all);
  const std::string out = (dir.path / "v.mp4").string();
  bool threw = false;
  try {
    FfmpegEncoder encoder({320, 240, 30}, fake.string(), out);
    // Far more than a pipe buffer, so the write must notice the reader is gone.
    for (int i = 0; i < 50; ++i) encoder.write_frame(grey_frame(320, 240, 7).data());
    encoder.finish();
  } catch (const RenderError& e) {
    threw = true;
    CHECK(std::string(e.what()).find("codec exploded") != std::string::npos);
  }
  CHECK(threw);
  CHECK(!fs::exists(out));
  CHECK(dir.count() == 1);  // only the fake program
}

TEST_CASE("ffmpeg: odd sizes and missing folders are refused before ffmpeg starts") {
  CHECK_THROWS_WITH_AS(FfmpegEncoder({33, 32, 30}, find_in_path("ffmpeg"), "/tmp/x.mp4"), doctest::Contains("even"),
                       RenderError);
  CHECK_THROWS_WITH_AS(FfmpegEncoder({32, 32, 30}, find_in_path("ffmpeg"), "/nonexistent/dir/x.mp4"),
                       doctest::Contains("does not exist"), RenderError);
}
