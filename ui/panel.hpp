#pragma once
// The control panel: material, limits and solver parameters of the live scene, live
// statistics, and the pause / step / reset / record buttons. Immediate mode: draw() builds
// the widgets of one ImGui frame and returns what the user asked for; the caller applies it
// (LiveScene rebuilds on a parameter change). Widgets are found by their label, so that a
// session script can say "drag slider 'E' to 2e5" (widget_rect).
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ui/live_scene.hpp"

namespace sinew {

struct PanelStats {
  std::deque<double> step_ms;                          // recent frames' simulation time, ms
  std::map<std::string, std::deque<double>> stage_ms;  // the same per stage (same length)
  std::vector<std::pair<std::string, double>> stages;  // last frame, ms per stage
  std::map<std::string, int> rows;                     // active rows by kind
  std::map<std::string, double> violation;             // worst violation by kind
  std::map<std::string, int> iterations;               // by solver
  double sim_per_wall = 0;                             // simulated seconds per wall second
  bool paused = false, recording = false;
  bool timings = true;                                 // false: wall-clock figures are not drawn
  int threads = 1;
  int over_budget = 0;                                 // frames over the budget_ms so far
};

struct PanelRequests {
  bool toggle_pause = false, step = false, reset = false, toggle_record = false;
  std::vector<std::pair<std::string, double>> parameters;  // name, new value (LiveScene names)
  std::string material_model, strain_mode;                 // empty: unchanged
  int threads = 0;                                         // 0: unchanged
};

struct WidgetRect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// How a slider maps its value to its track: linear in the value or in log10 of it.
struct SliderRange {
  double lo = 0, hi = 1;
  bool log = false;
};

class Panel {
 public:
  PanelRequests draw(const LiveScene& scene, const PanelStats& stats);
  // The rectangle (pixels, top-left origin) of the widget labelled `label` in the last
  // frame drawn; false if no such widget was drawn.
  bool widget_rect(const std::string& label, WidgetRect& out) const;
  // The track of parameter slider `label`; false if it is not a slider.
  static bool slider_range(const std::string& label, SliderRange& out);
  // Where to put the pointer on slider `label` (drawn in the last frame) to set `value`.
  bool slider_x(const std::string& label, double value, float& x) const;

 private:
  void slider(const LiveScene& scene, const std::string& name, PanelRequests& out);
  void remember(const std::string& label);
  std::map<std::string, WidgetRect> m_rects;
  std::map<std::string, double> m_editing;  // slider positions while dragged
};

}  // namespace sinew
