// Scripted sessions end to end (off-screen EGL, the panel drawn): a slider drag changes E in
// the engine, a grab-and-drag holds the grabbed point on the cursor's path, the same script
// gives the same state, and expectations report what they measured.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "engine/core/error.hpp"
#include "render/image.hpp"
#include "ui/panel.hpp"
#include "ui/session_runner.hpp"

using namespace sinew;

namespace {

const std::string kBeam = std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_beam_150kPa.json";

SessionResult run_text(const std::string& events, int frames, std::string* log_out = nullptr,
                       const std::string& top = "") {
  const std::string text = R"({"scene": ")" + kBeam + R"(", "frames": )" + std::to_string(frames) + top +
                           R"(, "events": [)" + events + "]}";
  const SessionScript script = parse_session_text(text, "test_session", ".");
  SessionOptions options;
  options.progress = false;
  options.threads = 1;
  std::ostringstream log;
  const SessionResult result = run_session(script, options, log);
  if (log_out) *log_out = log.str();
  return result;
}

}  // namespace

TEST_CASE("session: dragging the E slider rebuilds the engine with the new E, and the beam sags less") {
  const std::string expect_tip = R"({"frame": 60, "do": "expect", "quantity": "body.beam.min.y", "above": -10})";
  std::string log;
  const SessionResult dragged = run_text(
      R"({"frame": 3, "do": "drag_slider", "widget": "E", "to": 2e6, "frames": 5},
         {"frame": 20, "do": "expect", "quantity": "model.E", "above": 0},)" + expect_tip, 60, &log);
  INFO(log);
  REQUIRE(dragged.measured.count("events[1]"));
  // The pointer lands on whole pixels (ImGui floors it): the E track spans 6 decades over
  // 220 - 4 - 10 = 206 px, so the nearest pixel is within 0.5 * 6 / 206 decades (3.4 %).
  const double E = dragged.measured.at("events[1]");
  CHECK(std::abs(std::log10(E / 2e6)) <= 0.5 * 6 / 206.0 + 1e-9);
  const SessionResult untouched = run_text(expect_tip, 60);
  // 13x stiffer: the free end hangs far higher than the 150 kPa beam's.
  CHECK(dragged.measured.at("events[2]") > untouched.measured.at("events[0]") + 0.05);
}

TEST_CASE("session: a grabbed point follows the dragged target") {
  // The beam's free end (x = 0.5) is grabbed and lifted 0.2 m over 30 frames, then held.
  std::string log;
  const SessionResult r = run_text(
      R"({"frame": 1, "do": "grab", "point": [0.5, 0, 0]},
         {"frame": 1, "do": "drag_grab", "to": [0.45, 0.2, 0], "frames": 30},
         {"frame": 15, "do": "expect", "quantity": "grab.distance", "below": 1e9},
         {"frame": 31, "do": "expect", "quantity": "grab.distance", "below": 1e9},
         {"frame": 50, "do": "expect", "quantity": "grab.distance", "below": 1e9},
         {"frame": 50, "do": "expect", "quantity": "body.beam.max.y", "above": 0.15},
         {"frame": 50, "do": "expect", "quantity": "violation.attachment", "below": 1e9})",
      50, &log);
  INFO(log);
  CHECK(r.finite);
  CHECK(r.failed == 0);
  // The attachment rows hold the point at the end of every step to the SQP tolerance
  // (contact_tolerance, 1e-4 m) unless the SQP iteration cap binds.
  for (const char* e : {"events[2]", "events[3]", "events[4]", "events[6]"}) {
    CAPTURE(e);
    CHECK(r.measured.at(e) <= 1e-4 * (1 + 1e-9));
  }
}

TEST_CASE("session: the same script twice gives the same state hash") {
  const std::string events = R"({"frame": 2, "do": "grab", "point": [0.5, 0, 0]},
      {"frame": 2, "do": "drag_grab", "to": [0.5, 0.1, 0.1], "frames": 10},
      {"frame": 5, "do": "click", "widget": "Pause"}, {"frame": 12, "do": "key", "key": "space"},
      {"frame": 14, "do": "set", "parameter": "nu", "value": 0.4})";
  const SessionResult a = run_text(events, 25), b = run_text(events, 25);
  CHECK(a.finite);
  CHECK(a.frames == 25);
  CHECK(a.state_hash == b.state_hash);
}

TEST_CASE("session: without wall-clock timings on the panel, the same script draws the same pixels") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sinew_session_frames";
  std::filesystem::create_directories(dir);
  const std::string a = (dir / "a.png").string(), b = (dir / "b.png").string();
  auto events = [](const std::string& png) {
    return R"({"frame": 2, "do": "grab", "point": [0.5, 0, 0]},
              {"frame": 2, "do": "drag_grab", "to": [0.5, 0.1, 0], "frames": 8},
              {"frame": 3, "do": "drag_slider", "widget": "nu", "to": 0.4, "frames": 3},
              {"frame": 12, "do": "screenshot", "path": ")" + png + R"("})";
  };
  run_text(events(a), 12, nullptr, R"(, "timings": false)");
  run_text(events(b), 12, nullptr, R"(, "timings": false)");
  const Image first = read_png(a), second = read_png(b);
  CHECK(first.width == 1280);
  CHECK(mean_abs_difference(first, second) == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("session: clicking Pause stops the simulation until resumed") {
  const SessionResult r = run_text(
      R"({"frame": 5, "do": "click", "widget": "Pause"},
         {"frame": 10, "do": "expect", "quantity": "t", "above": 0},
         {"frame": 20, "do": "expect", "quantity": "t", "above": 0},
         {"frame": 21, "do": "key", "key": "space"},
         {"frame": 30, "do": "expect", "quantity": "t", "above": 0})",
      30);
  // The click's release lands at frame 7 (move, press, release): frames 8-20 do not step.
  CHECK(r.measured.at("events[1]") == doctest::Approx(r.measured.at("events[2]")));
  CHECK(r.measured.at("events[4]") > r.measured.at("events[2]"));
}

TEST_CASE("session: runtime errors name the event and its frame") {
  CHECK_THROWS_WITH_AS(run_text(R"({"frame": 2, "do": "click", "widget": "Nope"})", 5),
                       doctest::Contains("events[0] (frame 2): no widget labelled 'Nope'"), InputError);
  CHECK_THROWS_WITH_AS(run_text(R"({"frame": 2, "do": "set", "parameter": "nu", "value": 0.7})", 5),
                       doctest::Contains("events[0] (frame 2): parameter 'nu' must be a number in [0, 0.5)"),
                       InputError);
  CHECK_THROWS_WITH_AS(run_text(R"({"frame": 9, "do": "release"})", 5),
                       doctest::Contains("events[0]: frame 9 is after the last frame (5)"), InputError);
  CHECK_THROWS_WITH_AS(run_text(R"({"frame": 1, "do": "expect", "quantity": "speed", "below": 1})", 5),
                       doctest::Contains("unknown quantity 'speed'"), InputError);
}
