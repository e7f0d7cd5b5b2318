#include "ui/imgui_layer.hpp"

#include <imgui.h>
#include <backends/imgui_impl_opengl3.h>

#include <stdexcept>

namespace sinew {

ImGuiLayer::ImGuiLayer(int width, int height) : m_width(width), m_height(height) {
  IMGUI_CHECKVERSION();
  if (ImGui::GetCurrentContext()) throw std::logic_error("ImGuiLayer: one at a time");
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini: the same script gives the same frames
  io.LogFilename = nullptr;
  io.DisplaySize = ImVec2(float(width), float(height));
  ImGui::StyleColorsDark();
}

ImGuiLayer::~ImGuiLayer() {
  if (m_backend) ImGui_ImplOpenGL3_Shutdown();
  ImGui::DestroyContext();
}

void ImGuiLayer::frame(const Pointer& pointer, double dt, const std::function<void()>& build) {
  if (!m_backend) {
    if (!ImGui_ImplOpenGL3_Init("#version 330 core"))
      throw std::runtime_error("ImGui: the OpenGL 3 backend did not initialise (is libGL.so.1 installed?)");
    m_backend = true;
  }
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(float(m_width), float(m_height));
  io.DeltaTime = float(dt > 0 ? dt : 1.0 / 60.0);
  io.MousePos = pointer.x < 0 || pointer.y < 0 ? ImVec2(-FLT_MAX, -FLT_MAX) : ImVec2(pointer.x, pointer.y);
  io.MouseDown[0] = pointer.down;
  ImGui_ImplOpenGL3_NewFrame();
  ImGui::NewFrame();
  build();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace sinew
