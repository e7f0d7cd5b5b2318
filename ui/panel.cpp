#include "ui/panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/scene/scene.hpp"

namespace sinew {
namespace {

// ImGui 1.86 slider geometry (imgui_widgets.cpp, SliderBehaviorT): the grab travels inside
// the frame less 2 px of padding on each side and less its own width, GrabMinSize for a
// floating-point slider.
constexpr float kSliderPadding = 2;

double to_track(const SliderRange& r, double value) { return r.log ? std::log10(value) : value; }
double from_track(const SliderRange& r, double t) { return r.log ? std::pow(10.0, t) : t; }

const std::vector<const char*>& strain_modes() {
  static const std::vector<const char*> modes = {"hyperbolic", "orthogonal", "linear", "isotropic"};
  return modes;
}

}  // namespace

bool Panel::slider_range(const std::string& label, SliderRange& out) {
  static const std::map<std::string, SliderRange> ranges = {
      {"E", {1e3, 1e9, true}},          {"nu", {0.0, 0.499, false}},
      {"rho", {10, 1e4, true}},         {"Umax", {1e-3, 1e4, true}},
      {"smin.x", {0.5, 1, false}},      {"smin.y", {0.5, 1, false}},
      {"smin.z", {0.5, 1, false}},      {"smax.x", {1, 2, false}},
      {"smax.y", {1, 2, false}},        {"smax.z", {1, 2, false}},
      {"h", {1e-4, 0.1, true}},         {"pgs_max_iterations", {1, 1000, true}},
      {"sqp_max_iterations", {1, 100, true}}, {"newton_max_iterations", {1, 100, true}},
      {"sqp_tolerance", {1e-8, 1e-1, true}},  {"strain_tolerance", {1e-8, 1e-1, true}},
      {"newton_tolerance", {1e-12, 1e-1, true}}, {"budget_ms", {0, 100, false}}};
  const auto it = ranges.find(label);
  if (it == ranges.end()) return false;
  out = it->second;
  return true;
}

bool Panel::widget_rect(const std::string& label, WidgetRect& out) const {
  const auto it = m_rects.find(label);
  if (it == m_rects.end()) return false;
  out = it->second;
  return true;
}

bool Panel::slider_x(const std::string& label, double value, float& x) const {
  SliderRange r;
  WidgetRect rect;
  if (!slider_range(label, r) || !widget_rect(label, rect)) return false;
  const float grab = ImGui::GetCurrentContext() ? ImGui::GetStyle().GrabMinSize : 10.0f;
  const double lo = to_track(r, r.lo), hi = to_track(r, r.hi);
  const double t = std::clamp((to_track(r, value) - lo) / (hi - lo), 0.0, 1.0);
  const float usable = (rect.x1 - rect.x0) - 2 * kSliderPadding - grab;
  // ImGui floors the pointer position to whole pixels: aim at the nearest one.
  x = std::round(rect.x0 + kSliderPadding + 0.5f * grab + float(t) * usable);
  return true;
}

void Panel::remember(const std::string& label) {
  const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
  // The frame only, not the label text to its right: the track is what a drag targets.
  const float frame_width = ImGui::CalcItemWidth();
  m_rects[label] = {lo.x, lo.y, std::min(hi.x, lo.x + frame_width), hi.y};
}

void Panel::slider(const LiveScene& scene, const std::string& name, PanelRequests& out) {
  SliderRange r;
  slider_range(name, r);
  const double lo = to_track(r, r.lo), hi = to_track(r, r.hi);
  // While dragged (active in the last frame) the slider keeps its own position; otherwise
  // it shows the scene's value.
  const auto editing = m_editing.find(name);
  double track = editing != m_editing.end() ? editing->second
                                            : to_track(r, std::clamp(scene.parameter(name), r.lo, r.hi));
  char shown[64];
  const double value = scene.parameter(name);
  // A limit that is off (Umax 0, smax infinite) shows as such, not as the track's end.
  const bool off = !(value >= r.lo && value <= r.hi) || (name == "budget_ms" && value == 0);
  if (editing == m_editing.end() && off) std::snprintf(shown, sizeof shown, "off");
  else std::snprintf(shown, sizeof shown, "%.4g", from_track(r, track));
  ImGui::SliderScalar(name.c_str(), ImGuiDataType_Double, &track, &lo, &hi, shown);
  remember(name);
  if (ImGui::IsItemDeactivatedAfterEdit()) {
    double value = from_track(r, track);
    if (name.find("max_iterations") != std::string::npos) value = std::round(value);
    out.parameters.emplace_back(name, value);
  }
  if (ImGui::IsItemActive()) m_editing[name] = track;
  else m_editing.erase(name);
}

PanelRequests Panel::draw(const LiveScene& scene, const PanelStats& stats) {
  PanelRequests out;
  m_rects.clear();
  const ImGuiIO& io = ImGui::GetIO();
  constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                      ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize;
  // Controls on the left, statistics on the right; compact rows so that both fit 720 px.
  ImGui::GetStyle().ItemSpacing.y = 3;
  ImGui::GetStyle().FramePadding.y = 2;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("sinew", nullptr, kFixed);
  ImGui::PushItemWidth(220);  // sliders 220 px; labels (up to 21 characters) to their right

  if (ImGui::Button("Pause")) out.toggle_pause = true;
  remember("Pause");
  ImGui::SameLine();
  if (ImGui::Button("Step")) out.step = true;
  remember("Step");
  ImGui::SameLine();
  if (ImGui::Button("Reset")) out.reset = true;
  remember("Reset");
  ImGui::SameLine();
  if (ImGui::Button("Record")) out.toggle_record = true;
  remember("Record");
  ImGui::Text("%s%s  t = %.3f s", stats.paused ? "paused" : "running", stats.recording ? ", recording" : "",
              scene.world().state().t);

  const BodyDesc& body = scene.scene().bodies[size_t(scene.selected_body())];
  if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Text("body '%s'", body.name.c_str());
    const auto& names = material_model_names();
    int model = int(std::find(names.begin(), names.end(), body.material.model) - names.begin());
    std::vector<const char*> items;
    for (const auto& n : names) items.push_back(n.c_str());
    if (ImGui::Combo("model", &model, items.data(), int(items.size())) && model < int(names.size()))
      out.material_model = names[size_t(model)];
    remember("model");
    for (const char* p : {"E", "nu", "rho"}) slider(scene, p, out);
  }
  if (ImGui::CollapsingHeader("Limits", ImGuiTreeNodeFlags_DefaultOpen)) {
    slider(scene, "Umax", out);
    if (body.elements == "tet") {
      for (const char* p : {"smin.x", "smin.y", "smin.z", "smax.x", "smax.y", "smax.z"}) slider(scene, p, out);
      int mode = int(std::find_if(strain_modes().begin(), strain_modes().end(),
                                  [&](const char* m) { return body.strain_limit.mode == m; }) -
                     strain_modes().begin());
      if (ImGui::Combo("projection", &mode, strain_modes().data(), int(strain_modes().size())))
        out.strain_mode = strain_modes()[size_t(mode)];
      remember("projection");
    }
  }
  if (ImGui::CollapsingHeader("Solver", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (const char* p : {"h", "pgs_max_iterations", "sqp_max_iterations", "newton_max_iterations",
                          "sqp_tolerance", "strain_tolerance", "newton_tolerance", "budget_ms"})
      slider(scene, p, out);
    int threads = stats.threads;
    if (ImGui::SliderInt("threads", &threads, 1, 16)) out.threads = threads;
    remember("threads");
  }
  ImGui::PopItemWidth();
  ImGui::End();

  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 8, 8), ImGuiCond_Always, ImVec2(1, 0));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("live", nullptr, kFixed);
  if (stats.timings) {
    std::vector<float> history(stats.step_ms.begin(), stats.step_ms.end());
    const float top = history.empty() ? 1.0f : *std::max_element(history.begin(), history.end());
    char caption[64];
    std::snprintf(caption, sizeof caption, "%.2f ms", history.empty() ? 0.0 : double(history.back()));
    ImGui::PlotLines("frame ms", history.data(), int(history.size()), 0, caption, 0.0f, top * 1.1f, ImVec2(220, 50));
    // One small plot per stage that took time recently, on the total's scale.
    for (const auto& [stage, ms] : stats.stages) {
      const auto it = stats.stage_ms.find(stage);
      if (it == stats.stage_ms.end() || *std::max_element(it->second.begin(), it->second.end()) <= 0) continue;
      const std::vector<float> series(it->second.begin(), it->second.end());
      std::snprintf(caption, sizeof caption, "%.3f ms", ms);
      ImGui::PlotLines(stage.c_str(), series.data(), int(series.size()), 0, caption, 0.0f, top * 1.1f, ImVec2(220, 22));
    }
    ImGui::Text("simulated / real time %.3f", stats.sim_per_wall);
    ImGui::Text("frames over budget %d", stats.over_budget);
  }
  {
    for (const auto& [kind, n] : stats.rows) ImGui::Text("rows %-10s %d", kind.c_str(), n);
    for (const auto& [kind, v] : stats.violation) ImGui::Text("worst %-9s %.3g", kind.c_str(), v);
    for (const auto& [solver, n] : stats.iterations) ImGui::Text("%-10s %d its", solver.c_str(), n);
  }
  ImGui::End();
  return out;
}

}  // namespace sinew
