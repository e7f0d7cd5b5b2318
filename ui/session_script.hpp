#pragma once
// A session script: a scene, and a timeline of events at frames (or times) that drive the
// panel and the simulation as a user would (pointer on widgets, keys, grabbing a surface
// point and dragging it, camera moves, parameter sets, recording, screenshots) plus
// expectations that make the script an acceptance test. Format: docs/sessions.md.
#include <optional>
#include <string>
#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

enum class SessionEventType {
  Pointer,      // move / press / release at a pixel or on a widget
  Click,        // a widget: move there, press, release (3 frames)
  DragSlider,   // a slider widget to a value over `frames` frames
  Key,          // "space" pause, "s" step, "r" reset, "c" record
  Grab,         // the surface point under a pixel (ray pick) or nearest to a point
  DragGrab,     // the grabbed point's target along a straight path to `point` over `frames`
  Release,      // lets the grabbed point go
  Camera,       // orbit and elevation, degrees
  Set,          // a parameter (number), material model or strain projection mode
  RecordStart,  // starts recording (needs --record or "path")
  RecordStop,
  Screenshot,   // a PNG of this frame
  Expect,       // a quantity compared with a bound, checked after this frame
};

struct SessionEvent {
  int index = 0;          // in "events"
  std::string path;       // JSON path, for messages: "events[3]"
  SessionEventType type = SessionEventType::Pointer;
  int frame = -1;         // from "frame"; -1: from "time"
  double time = -1;       // s
  std::string action;     // Pointer: "move", "press" or "release"
  std::optional<Eigen::Vector2f> pixel;  // from the top-left corner
  std::string widget;     // a panel label ("E", "Reset"...)
  double value = 0;       // DragSlider target, Set value
  int frames = 10;        // DragSlider, DragGrab: duration in frames
  std::string key;        // Key
  std::optional<Vec3> point;  // Grab (nearest surface point), DragGrab (end of the path)
  double orbit_deg = 30, elevation_deg = 20;  // Camera
  std::string parameter;  // Set: a LiveScene parameter, "material_model" or "strain_mode"
  std::string text;       // Set: material model or strain mode name
  std::string file;       // Screenshot, RecordStart: output path (relative to the working dir)
  std::string quantity;   // Expect: see docs/sessions.md
  std::optional<double> below, above;  // Expect: value < below, value > above
};

struct SessionScript {
  std::string name;        // file name, for messages
  std::string scene_path;  // resolved against the script's folder
  int frames = 0;          // 0: the scene's
  int width = 1280, height = 720;
  bool panel = true;
  bool timings = true;     // the panel shows wall-clock times (false: identical pixels run to run)
  std::string body;        // the body the panel edits ("" = the first)
  std::vector<SessionEvent> events;  // in file order
};

// Throws InputError naming the file, the JSON path (events[i].key) and what was expected.
SessionScript load_session(const std::string& path);
SessionScript parse_session_text(const std::string& text, const std::string& name, const std::string& base_dir);

}  // namespace sinew
