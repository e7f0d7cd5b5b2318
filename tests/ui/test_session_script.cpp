// Session scripts are checked before anything runs: each error names the file, the JSON
// path of the event (events[i].key) and what was expected.
#include <doctest/doctest.h>

#include <string>

#include "engine/core/error.hpp"
#include "ui/session_script.hpp"

using namespace sinew;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_session_text(text, "s.json", "/base");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string with_event(const std::string& event) {
  return R"({"scene": "a.json", "events": [{"frame": 1, "do": "release"}, )" + event + "]}";
}

}  // namespace

TEST_CASE("session_script: a valid script") {
  const SessionScript s = parse_session_text(
      R"({"scene": "scenes/a.json", "frames": 30, "size": [800, 600], "panel": false, "body": "b",
          "events": [{"time": 0.5, "do": "drag_slider", "widget": "E", "to": 2e5},
                     {"frame": 3, "do": "grab", "pixel": [10, 20]},
                     {"frame": 4, "do": "expect", "quantity": "t", "below": 1, "above": 0}]})",
      "s.json", "/base");
  CHECK(s.scene_path == "/base/scenes/a.json");
  CHECK(s.frames == 30);
  CHECK(s.width == 800);
  CHECK(!s.panel);
  REQUIRE(s.events.size() == 3);
  CHECK(s.events[0].type == SessionEventType::DragSlider);
  CHECK(s.events[0].frame == -1);
  CHECK(s.events[0].time == 0.5);
  CHECK(s.events[0].frames == 10);
  CHECK(s.events[1].pixel->y() == 20);
  CHECK(*s.events[2].below == 1);
}

TEST_CASE("session_script: errors name the event index and JSON path") {
  CHECK(error_of("{").find("s.json: not valid JSON") == 0);
  // Found by tools/fuzz (fuzz_session_script): a number too large for a double is
  // nlohmann's out_of_range, not a parse_error; it escaped as an uncaught exception.
  CHECK(error_of(R"({"scene": "a", "frames": 1.9e4444})").find("s.json: not valid JSON") == 0);
  CHECK(error_of(R"({"events": []})") == "s.json: a session needs \"scene\" (a scene file)");
  CHECK(error_of(R"({"scene": "a", "speed": 1})").find("s.json: speed: unknown key") == 0);
  CHECK(error_of(with_event(R"({"frame": 2, "do": "jump"})")) ==
        "s.json: events[1].do: expected one of pointer, click, drag_slider, key, grab, drag_grab, release, "
        "camera, set, record_start, record_stop, screenshot, expect, got \"jump\"");
  CHECK(error_of(with_event(R"({"do": "release"})")) ==
        "s.json: events[1]: expected exactly one of \"frame\" (integer >= 0) and \"time\" (s), got {\"do\":\"release\"}");
  CHECK(error_of(with_event(R"({"frame": 2.5, "do": "release"})")) ==
        "s.json: events[1].frame: expected an integer >= 0, got 2.5");
  CHECK(error_of(with_event(R"({"frame": 2, "do": "click"})")) == "s.json: events[1]: a 'click' event needs \"widget\"");
  CHECK(error_of(with_event(R"({"frame": 2, "do": "grab", "pixel": [1]})")) ==
        "s.json: events[1].pixel: expected a pixel [x, y] (from the top-left corner), got [1]");
  CHECK(error_of(with_event(R"({"frame": 2, "do": "grab", "pixel": [1, 2], "point": [0, 0, 0]})")).find(
            "s.json: events[1]: expected exactly one of \"pixel\" and \"point\"") == 0);
  CHECK(error_of(with_event(R"({"frame": 2, "do": "key", "key": "q"})")).find("s.json: events[1].key: expected \"space\"") == 0);
  CHECK(error_of(with_event(R"({"frame": 2, "do": "expect", "quantity": "t"})")).find(
            "s.json: events[1]: expected an expectation with \"below\" and/or \"above\"") == 0);
  CHECK(error_of(with_event(R"({"frame": 2, "do": "release", "widget": "E"})")) ==
        "s.json: events[1].widget: unknown key for a 'release' event");
}
