#pragma once
// The off-screen target: a multisampled colour + depth/stencil framebuffer for drawing,
// resolved into a single-sample one for readback (glReadPixels cannot read MSAA).
#include <cstdint>

#include "render/gl.hpp"

namespace sinew {

class Framebuffer {
 public:
  // `samples` is clamped to GL_MAX_SAMPLES; 1 or less draws without MSAA. Throws RenderError
  // if the framebuffer is incomplete or the size exceeds GL_MAX_RENDERBUFFER_SIZE.
  Framebuffer(int width, int height, int samples);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  int width() const { return m_width; }
  int height() const { return m_height; }
  int samples() const { return m_samples; }

  void bind_for_drawing() const;
  // Resolves the samples into the single-sample buffer.
  void resolve() const;
  // Tightly packed RGB, GL order: the first row is the bottom of the image.
  void read_rgb(uint8_t* dst) const;

 private:
  int m_width, m_height, m_samples = 0;
  GLuint m_draw_fbo = 0, m_resolve_fbo = 0;
  GLuint m_color = 0, m_depth = 0, m_resolved = 0;
};

}  // namespace sinew
