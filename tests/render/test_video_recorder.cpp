// The recorder with and without its capture thread: frame count, size, row order, failures.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "render/render_error.hpp"
#include "render/video_recorder.hpp"
#include "tests/render/video_test_support.hpp"

using namespace sinew;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("sinew_video_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// GL order: the first rows in memory are the bottom of the picture; make them blue, the
// top half red.
void fill_blue_bottom_red_top(uint8_t* rgb, int w, int h) {
  for (int row = 0; row < h; ++row)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = rgb + 3 * (size_t(row) * w + x);
      const bool bottom = row < h / 2;
      p[0] = bottom ? 0 : 220, p[1] = 20, p[2] = bottom ? 220 : 0;
    }
}

}  // namespace

TEST_CASE("recorder: 30 frames in, 30 frames out, upright, with and without the capture thread") {
  const fs::path dir = temp_dir("count");
  for (bool threaded : {true, false}) {
    CAPTURE(threaded);
    VideoSettings s;
    s.path = (dir / (threaded ? "t.mp4" : "s.mp4")).string();
    s.format = {96, 64, 30};
    s.capture_thread = threaded;
    VideoRecorder recorder(s);
    for (int i = 0; i < 30; ++i) recorder.add_frame([](uint8_t* rgb) { fill_blue_bottom_red_top(rgb, 96, 64); });
    recorder.finish();
    CHECK(recorder.frames() == 30);
    const test::VideoInfo info = test::probe_video(s.path);
    INFO(info.raw);
    CHECK(info.frames == 30);
    CHECK(info.width == 96);
    CHECK(info.height == 64);
    const std::vector<uint8_t> first = test::first_frame_rgb(s.path);
    REQUIRE(first.size() == 3u * 96 * 64);
    const uint8_t* top_left = &first[3 * (2 * 96 + 2)];
    const uint8_t* bottom_left = &first[3 * (61 * 96 + 2)];
    CHECK(top_left[0] > 150);  // red on top: rows were flipped from GL order
    CHECK(top_left[2] < 80);
    CHECK(bottom_left[2] > 150);
    CHECK(bottom_left[0] < 80);
  }
  fs::remove_all(dir);
}

TEST_CASE("recorder: an encoder failure reaches the caller and no video is left") {
  const fs::path dir = temp_dir("fail");
  const fs::path fake = dir / "fake-ffmpeg";
  std::ofstream(fake) << "#!/bin/sh\necho 'no space left' >&2\nexit 1\n";
  fs::permissions(fake, fs::perms::owner_all);
  for (bool threaded : {true, false}) {
    CAPTURE(threaded);
    VideoSettings s;
    s.path = (dir / "v.mp4").string();
    s.format = {320, 240, 30};
    s.ffmpeg = fake.string();
    s.capture_thread = threaded;
    bool threw = false;
    try {
      VideoRecorder recorder(s);
      for (int i = 0; i < 60; ++i) recorder.add_frame([](uint8_t* rgb) { rgb[0] = 1; });
      recorder.finish();
    } catch (const RenderError& e) {
      threw = true;
      CHECK(std::string(e.what()).find("no space left") != std::string::npos);
    }
    CHECK(threw);
    CHECK(!fs::exists(s.path));
  }
  fs::remove_all(dir);
}
