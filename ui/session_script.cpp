#include "ui/session_script.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "engine/core/error.hpp"

namespace sinew {
namespace {

using nlohmann::json;

const std::map<std::string, SessionEventType>& event_types() {
  static const std::map<std::string, SessionEventType> types = {
      {"pointer", SessionEventType::Pointer},       {"click", SessionEventType::Click},
      {"drag_slider", SessionEventType::DragSlider}, {"key", SessionEventType::Key},
      {"grab", SessionEventType::Grab},             {"drag_grab", SessionEventType::DragGrab},
      {"release", SessionEventType::Release},       {"camera", SessionEventType::Camera},
      {"set", SessionEventType::Set},               {"record_start", SessionEventType::RecordStart},
      {"record_stop", SessionEventType::RecordStop}, {"screenshot", SessionEventType::Screenshot},
      {"expect", SessionEventType::Expect}};
  return types;
}

// Keys each event type accepts besides "do", "frame" and "time".
const std::map<SessionEventType, std::set<std::string>>& event_keys() {
  using T = SessionEventType;
  static const std::map<T, std::set<std::string>> keys = {
      {T::Pointer, {"action", "pixel", "widget"}}, {T::Click, {"widget"}},
      {T::DragSlider, {"widget", "to", "frames"}}, {T::Key, {"key"}},
      {T::Grab, {"pixel", "point"}},               {T::DragGrab, {"to", "frames"}},
      {T::Release, {}},                            {T::Camera, {"orbit_deg", "elevation_deg"}},
      {T::Set, {"parameter", "value"}},            {T::RecordStart, {"path"}},
      {T::RecordStop, {}},                         {T::Screenshot, {"path"}},
      {T::Expect, {"quantity", "below", "above"}}};
  return keys;
}

// A JSON value with its path, failing with "FILE: PATH: expected WHAT, got VALUE".
struct Value {
  const json& v;
  std::string path;
  const std::string& file;

  [[noreturn]] void expected(const std::string& what) const {
    std::string got = v.dump();
    if (got.size() > 60) got = got.substr(0, 57) + "...";
    throw InputError(file + ": " + path + ": expected " + what + ", got " + got);
  }
  Value at(const std::string& key) const { return {v.at(key), path + "." + key, file}; }
  double number() const {
    if (!v.is_number() || !std::isfinite(v.get<double>())) expected("a number");
    return v.get<double>();
  }
  int integer(int lo) const {
    if (!v.is_number() || v.get<double>() != std::floor(v.get<double>()) || v.get<double>() < lo ||
        v.get<double>() > 1e7)
      expected("an integer >= " + std::to_string(lo));
    return int(v.get<double>());
  }
  std::string string() const {
    if (!v.is_string() || v.get<std::string>().empty()) expected("a non-empty string");
    return v.get<std::string>();
  }
  Eigen::Vector2f pixel() const {
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
      expected("a pixel [x, y] (from the top-left corner)");
    return {v[0].get<float>(), v[1].get<float>()};
  }
  Vec3 point() const {
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      expected("a point [x, y, z] in metres");
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  }
};

SessionEvent parse_event(const Value& node, int index) {
  if (!node.v.is_object()) node.expected("an event object with \"do\" and \"frame\" or \"time\"");
  SessionEvent e;
  e.index = index;
  e.path = node.path;
  if (!node.v.contains("do")) node.expected("an event with \"do\": one of pointer, click, drag_slider, key, "
                                           "grab, drag_grab, release, camera, set, record_start, record_stop, "
                                           "screenshot, expect");
  const std::string kind = node.at("do").string();
  const auto type = event_types().find(kind);
  if (type == event_types().end())
    node.at("do").expected("one of pointer, click, drag_slider, key, grab, drag_grab, release, camera, set, "
                           "record_start, record_stop, screenshot, expect");
  e.type = type->second;
  const std::set<std::string>& allowed = event_keys().at(e.type);
  for (const auto& [key, value] : node.v.items())
    if (key != "do" && key != "frame" && key != "time" && !allowed.count(key))
      throw InputError(node.file + ": " + node.path + "." + key + ": unknown key for a '" + kind + "' event");
  const bool has_frame = node.v.contains("frame"), has_time = node.v.contains("time");
  if (has_frame == has_time) node.expected("exactly one of \"frame\" (integer >= 0) and \"time\" (s)");
  if (has_frame) e.frame = node.at("frame").integer(0);
  if (has_time) {
    e.time = node.at("time").number();
    if (e.time < 0) node.at("time").expected("a time >= 0");
  }
  auto required = [&](const std::string& key) {
    if (!node.v.contains(key)) throw InputError(node.file + ": " + node.path + ": a '" + kind + "' event needs \"" + key + "\"");
    return node.at(key);
  };
  using T = SessionEventType;
  switch (e.type) {
    case T::Pointer: {
      e.action = required("action").string();
      if (e.action != "move" && e.action != "press" && e.action != "release")
        node.at("action").expected("\"move\", \"press\" or \"release\"");
      if (node.v.contains("pixel")) e.pixel = node.at("pixel").pixel();
      if (node.v.contains("widget")) e.widget = node.at("widget").string();
      if (e.pixel.has_value() == !e.widget.empty()) node.expected("exactly one of \"pixel\" and \"widget\"");
      break;
    }
    case T::Click: e.widget = required("widget").string(); break;
    case T::DragSlider:
      e.widget = required("widget").string();
      e.value = required("to").number();
      if (node.v.contains("frames")) e.frames = node.at("frames").integer(1);
      break;
    case T::Key:
      e.key = required("key").string();
      if (e.key != "space" && e.key != "s" && e.key != "r" && e.key != "c")
        node.at("key").expected("\"space\" (pause), \"s\" (step), \"r\" (reset) or \"c\" (record)");
      break;
    case T::Grab:
      if (node.v.contains("pixel")) e.pixel = node.at("pixel").pixel();
      if (node.v.contains("point")) e.point = node.at("point").point();
      if (e.pixel.has_value() == e.point.has_value()) node.expected("exactly one of \"pixel\" and \"point\"");
      break;
    case T::DragGrab:
      e.point = required("to").point();
      if (node.v.contains("frames")) e.frames = node.at("frames").integer(1);
      break;
    case T::Camera:
      e.orbit_deg = required("orbit_deg").number();
      e.elevation_deg = required("elevation_deg").number();
      if (std::abs(e.elevation_deg) >= 90) node.at("elevation_deg").expected("an angle in (-90, 90) degrees");
      break;
    case T::Set: {
      e.parameter = required("parameter").string();
      const Value value = required("value");
      if (e.parameter == "material_model" || e.parameter == "strain_mode") e.text = value.string();
      else e.value = value.number();
      break;
    }
    case T::RecordStart:
      if (node.v.contains("path")) e.file = node.at("path").string();
      break;
    case T::Screenshot: e.file = required("path").string(); break;
    case T::Expect:
      e.quantity = required("quantity").string();
      if (node.v.contains("below")) e.below = node.at("below").number();
      if (node.v.contains("above")) e.above = node.at("above").number();
      if (!e.below && !e.above) node.expected("an expectation with \"below\" and/or \"above\"");
      break;
    case T::Release:
    case T::RecordStop: break;
  }
  return e;
}

}  // namespace

SessionScript parse_session_text(const std::string& text, const std::string& name, const std::string& base_dir) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for 1e999 (found by fuzzing)
    throw InputError(name + ": not valid JSON: " + e.what());
  }
  const Value top{root, "(root)", name};
  if (!root.is_object()) top.expected("a session object with \"scene\" and \"events\"");
  static const std::set<std::string> keys = {"scene", "frames", "size", "panel", "timings", "body", "events"};
  for (const auto& [key, value] : root.items())
    if (!keys.count(key))
      throw InputError(name + ": " + key + ": unknown key (expected scene, frames, size, panel, timings, body, events)");
  SessionScript s;
  s.name = name;
  if (!root.contains("scene")) throw InputError(name + ": a session needs \"scene\" (a scene file)");
  const Value scene{root.at("scene"), "scene", name};
  const std::filesystem::path scene_path(scene.string());
  s.scene_path = scene_path.is_absolute() ? scene_path.string() : (std::filesystem::path(base_dir) / scene_path).string();
  if (root.contains("frames")) s.frames = Value{root.at("frames"), "frames", name}.integer(1);
  if (root.contains("size")) {
    const Value size{root.at("size"), "size", name};
    if (!size.v.is_array() || size.v.size() != 2) size.expected("[width, height] in pixels");
    s.width = Value{size.v[0], "size[0]", name}.integer(64);
    s.height = Value{size.v[1], "size[1]", name}.integer(64);
  }
  if (root.contains("panel")) {
    if (!root.at("panel").is_boolean()) Value{root.at("panel"), "panel", name}.expected("true or false");
    s.panel = root.at("panel").get<bool>();
  }
  if (root.contains("timings")) {
    if (!root.at("timings").is_boolean()) Value{root.at("timings"), "timings", name}.expected("true or false");
    s.timings = root.at("timings").get<bool>();
  }
  if (root.contains("body")) s.body = Value{root.at("body"), "body", name}.string();
  if (root.contains("events")) {
    const Value events{root.at("events"), "events", name};
    if (!events.v.is_array()) events.expected("an array of events");
    for (size_t i = 0; i < events.v.size(); ++i)
      s.events.push_back(parse_event({events.v[i], "events[" + std::to_string(i) + "]", name}, int(i)));
  }
  return s;
}

SessionScript load_session(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the session script");
  std::stringstream text;
  text << in.rdbuf();
  return parse_session_text(text.str(), path, std::filesystem::path(path).parent_path().string());
}

}  // namespace sinew
