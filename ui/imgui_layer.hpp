#pragma once
// Dear ImGui (Debian's 1.86) drawn into the renderer's off-screen framebuffer through its
// OpenGL 3 backend. Input is synthetic: the session runner sets the pointer each frame
// (1.86 takes it through io.MousePos / io.MouseDown; the event API came in 1.87).
#include <functional>

namespace sinew {

struct Pointer {
  float x = -1, y = -1;  // pixels from the top-left corner; negative: outside the picture
  bool down = false;     // left button
};

class ImGuiLayer {
 public:
  ImGuiLayer(int width, int height);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  // One ImGui frame: `build` makes the widgets; then the frame is drawn into the bound
  // framebuffer. Call with the renderer's GL context current (Renderer::draw's overlay).
  void frame(const Pointer& pointer, double dt, const std::function<void()>& build);

 private:
  int m_width, m_height;
  bool m_backend = false;  // the GL backend is initialised lazily, in the first frame's context
};

}  // namespace sinew
