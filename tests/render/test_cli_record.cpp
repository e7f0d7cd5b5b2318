// `sinew run` with --record / --screenshot as a user meets it: the video has the frames the
// options promise, and a missing ffmpeg or EGL is a clear error before anything runs.
#include <doctest/doctest.h>

#include "tests/support/cli_runner.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "render/egl_context.hpp"
#include "render/render_error.hpp"
#include "tests/render/video_test_support.hpp"

namespace fs = std::filesystem;

namespace {

using Result = sinew::test::CliResult;
using sinew::test::run_sinew;
using sinew::test::TempDir;

// A small box dropped onto a plane; 60 fps output.
const char* kScene = R"({"fps": 60, "frames": 6,
  "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}],
  "bodies": [{"name": "b", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
    "transform": {"translate": [0, 0.3, 0]}, "material": {"E": 1e5, "nu": 0.3, "rho": 1000}}]})";

bool egl_available() {
  try {
    sinew::EglContext context;
    return true;
  } catch (const sinew::EglUnavailable& e) {
    MESSAGE("SKIPPED: no EGL on this machine, so nothing can be drawn: " << e.what());
    return false;
  }
}

}  // namespace

TEST_CASE("sinew run --record: the MP4 has one frame per video frame time, at the asked size") {
  if (!egl_available()) return;
  TempDir dir("ok");
  const std::string scene = dir.write("scene.json", kScene);
  // 6 simulated frames at 60 fps plus the initial state: 7 frames at the scene's rate.
  Result r = run_sinew("run " + scene + " --record " + (dir / "a.mp4") + " --size 160x96 --quiet");
  INFO(r.output);
  REQUIRE(r.code == 0);
  sinew::test::VideoInfo info = sinew::test::probe_video(dir / "a.mp4");
  INFO(info.raw);
  CHECK(info.frames == 7);
  CHECK(info.width == 160);
  CHECK(info.height == 96);
  CHECK(info.codec == "h264");
  CHECK(info.pix_fmt == "yuv420p");
  // At 30 fps the video keeps real time: times 0, 1/30, 2/30, 3/30 s of the 0.1 s run.
  r = run_sinew("run " + scene + " --record " + (dir / "b.mp4") +
                " --fps 30 --size 160x96 --wireframe --color-map volume --screenshot 3:" + (dir / "s.png") + " --quiet");
  REQUIRE(r.code == 0);
  info = sinew::test::probe_video(dir / "b.mp4");
  CHECK(info.frames == 4);
  CHECK(fs::file_size(dir / "s.png") > 1000);
  // Nothing else: no temporary video or log left behind.
  long files = std::distance(fs::directory_iterator(dir.path), fs::directory_iterator());
  CHECK(files == 4);  // scene, a.mp4, b.mp4, s.png
}

TEST_CASE("sinew run --record without ffmpeg in PATH: a clear error before the run, no video") {
  TempDir dir("noffmpeg");
  const std::string scene = dir.write("scene.json", kScene);
  fs::create_directories(dir.path / "empty");
  const Result r = run_sinew("run " + scene + " --record " + (dir / "v.mp4"), "PATH=" + (dir / "empty"));
  INFO(r.output);
  CHECK(r.code != 0);
  CHECK(r.output.find("ffmpeg") != std::string::npos);
  CHECK(r.output.find("not in PATH") != std::string::npos);
  CHECK(r.output.find("scene '") == std::string::npos);  // stopped before the scene was even built
  CHECK(!fs::exists(dir / "v.mp4"));
}

TEST_CASE("sinew run --screenshot without any EGL driver: the error names what was tried") {
  TempDir dir("noegl");
  const std::string scene = dir.write("scene.json", kScene);
  fs::create_directories(dir.path / "no_vendors");
  // GLVND's libEGL loads the vendor libraries (Mesa, NVIDIA...) listed in
  // __EGL_VENDOR_LIBRARY_DIRS; an empty folder leaves it with none, exactly as on a machine
  // without libegl-mesa0. FILENAMES would take precedence, so it is cleared.
  const Result r = run_sinew("run " + scene + " --screenshot 0:" + (dir / "s.png"),
                             "env -u __EGL_VENDOR_LIBRARY_FILENAMES __EGL_VENDOR_LIBRARY_DIRS=" + (dir / "no_vendors"));
  INFO(r.output);
  CHECK(r.code != 0);
  CHECK(r.output.find("without a display server") != std::string::npos);
  CHECK(r.output.find("EGL_MESA_platform_surfaceless") != std::string::npos);
  CHECK(r.output.find("EGL_EXT_platform_device") != std::string::npos);
  CHECK(r.output.find("scene '") == std::string::npos);
  CHECK(!fs::exists(dir / "s.png"));
}

TEST_CASE("sinew run: bad recording options are usage errors (exit 2) that name the option") {
  TempDir dir("bad");
  const std::string scene = dir.write("scene.json", kScene);
  const std::pair<std::string, std::string> cases[] = {
      {"--record " + (dir / "v.mp4") + " --size 161x96", "even"},
      {"--screenshot 0:" + (dir / "s.png") + " --size 1280", "WxH"},
      {"--screenshot 0:" + (dir / "s.png") + " --size 8x8", "16..8192"},
      {"--screenshot 0:" + (dir / "s.png") + " --color-map strain", "energy, volume or none"},
      {"--screenshot five:" + (dir / "s.png"), "--screenshot"},
      {"--screenshot 3", "FRAME:OUT.png"},
      {"--record " + (dir / "v.mp4") + " --fps 0", "--fps"},
  };
  for (const auto& [options, words] : cases) {
    const Result r = run_sinew("run " + scene + " " + options);
    INFO(options << "\n" << r.output);
    CHECK(r.code == 2);
    CHECK(r.output.find(words) != std::string::npos);
  }
  CHECK(!fs::exists(dir / "v.mp4"));
  CHECK(!fs::exists(dir / "s.png"));
}

TEST_CASE("sinew run: a screenshot after the last frame is refused; --help lists the recording options") {
  if (egl_available()) {
    TempDir dir("late");
    const std::string scene = dir.write("scene.json", kScene);
    const Result r = run_sinew("run " + scene + " --screenshot 7:" + (dir / "s.png"));
    INFO(r.output);
    CHECK(r.code == 2);
    CHECK(r.output.find("after the last frame") != std::string::npos);
  }
  const Result help = run_sinew("run --help");
  CHECK(help.code == 0);
  for (const char* option : {"--record", "--fps", "--size", "--screenshot", "--wireframe", "--color-map"})
    CHECK(help.output.find(option) != std::string::npos);
}
