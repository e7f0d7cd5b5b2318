#include "render/framebuffer.hpp"

#include <algorithm>
#include <string>

#include "render/render_error.hpp"

namespace sinew {
namespace {

void check_complete(GLuint fbo, const char* which) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError(std::string("the ") + which + " framebuffer is incomplete (status 0x" +
                      std::to_string(status) + ")");
}

}  // namespace

Framebuffer::Framebuffer(int width, int height, int samples) : m_width(width), m_height(height) {
  GLint max_size = 0, max_samples = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (width < 1 || height < 1 || width > max_size || height > max_size)
    throw RenderError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                      " is outside 1.." + std::to_string(max_size) + " per side");
  m_samples = samples > 1 ? std::min(samples, static_cast<int>(max_samples)) : 0;

  glGenRenderbuffers(1, &m_color);
  glBindRenderbuffer(GL_RENDERBUFFER, m_color);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples, GL_RGBA8, width, height);
  glGenRenderbuffers(1, &m_depth);
  glBindRenderbuffer(GL_RENDERBUFFER, m_depth);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples, GL_DEPTH24_STENCIL8, width, height);
  glGenFramebuffers(1, &m_draw_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, m_draw_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_color);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_depth);
  check_complete(m_draw_fbo, "multisampled");

  glGenRenderbuffers(1, &m_resolved);
  glBindRenderbuffer(GL_RENDERBUFFER, m_resolved);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glGenFramebuffers(1, &m_resolve_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, m_resolve_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_resolved);
  check_complete(m_resolve_fbo, "resolve");
}

Framebuffer::~Framebuffer() {
  glDeleteFramebuffers(1, &m_draw_fbo);
  glDeleteFramebuffers(1, &m_resolve_fbo);
  glDeleteRenderbuffers(1, &m_color);
  glDeleteRenderbuffers(1, &m_depth);
  glDeleteRenderbuffers(1, &m_resolved);
}

void Framebuffer::bind_for_drawing() const {
  glBindFramebuffer(GL_FRAMEBUFFER, m_draw_fbo);
  glViewport(0, 0, m_width, m_height);
}

void Framebuffer::resolve() const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m_draw_fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_resolve_fbo);
  glBlitFramebuffer(0, 0, m_width, m_height, 0, 0, m_width, m_height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void Framebuffer::read_rgb(uint8_t* dst) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m_resolve_fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);  // rows of 3 * width bytes, no padding
  glReadPixels(0, 0, m_width, m_height, GL_RGB, GL_UNSIGNED_BYTE, dst);
}

}  // namespace sinew
