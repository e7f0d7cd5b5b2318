#pragma once
// An OpenGL 3.3 core context without a window or display server, current on the thread
// that created it. Tries Mesa's surfaceless platform, then each EGL device
// (EGL_EXT_platform_device); EGL_DEFAULT_DISPLAY is never used because it needs X or Wayland.
#include <string>

namespace sinew {

class EglContext {
 public:
  // Throws EglUnavailable listing every platform tried and why each failed.
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Makes this context current on the calling thread, if it is not already (several
  // contexts may live on one thread; each GL call goes to the current one).
  void make_current() const;

  // e.g. "surfaceless: OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)"
  const std::string& description() const { return m_description; }

 private:
  void* m_display = nullptr;  // EGLDisplay
  void* m_context = nullptr;  // EGLContext
  std::string m_description;
};

}  // namespace sinew
