#include "render/egl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <sstream>
#include <vector>

#include "render/gl.hpp"
#include "render/render_error.hpp"

namespace sinew {
namespace {

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::string egl_error() {
  const EGLint e = eglGetError();
  switch (e) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: {
      std::ostringstream s;
      s << "EGL error 0x" << std::hex << e;
      return s.str();
    }
  }
}

// Initialises `display` and makes a 3.3 core context current without a surface.
// Returns the context, or nullptr with `why` set.
EGLContext make_context(EGLDisplay display, std::string& why) {
  if (display == EGL_NO_DISPLAY) return why = "no display (" + egl_error() + ")", nullptr;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return why = "eglInitialize failed (" + egl_error() + ")", nullptr;
  const char* ext = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_extension(ext, "EGL_KHR_surfaceless_context"))
    return why = "display lacks EGL_KHR_surfaceless_context", nullptr;
  if (!eglBindAPI(EGL_OPENGL_API)) return why = "eglBindAPI(EGL_OPENGL_API) failed (" + egl_error() + ")", nullptr;

  EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
  if (!has_extension(ext, "EGL_KHR_no_config_context")) {
    // Surface type 0: we never make a surface, so do not demand window support.
    const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display, want, &config, 1, &count) || count < 1)
      return why = "no config with EGL_OPENGL_BIT (" + egl_error() + ")", nullptr;
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) return why = "no OpenGL 3.3 core context (" + egl_error() + ")", nullptr;
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    why = "eglMakeCurrent failed (" + egl_error() + ")";
    eglDestroyContext(display, context);
    return nullptr;
  }
  return context;
}

}  // namespace

EglContext::EglContext() {
  // Client extensions are empty when no EGL vendor library (e.g. libegl-mesa0) is found.
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  std::vector<std::string> tried;
  auto get_display = has_extension(client, "EGL_EXT_platform_base")
                         ? reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"))
                         : nullptr;
  std::string why;
  auto attempt = [&](const std::string& name, EGLDisplay display) {
    if (void* context = make_context(display, why)) {
      m_display = display, m_context = context;
      m_description = name + ": " + reinterpret_cast<const char*>(glGetString(GL_VERSION)) + ", " +
                      reinterpret_cast<const char*>(glGetString(GL_RENDERER));
      return true;
    }
    tried.push_back(name + " (" + why + ")");
    return false;
  };

  if (!get_display || !has_extension(client, "EGL_MESA_platform_surfaceless"))
    tried.push_back("EGL_MESA_platform_surfaceless (not offered)");
  // The surfaceless platform's only valid native display is EGL_DEFAULT_DISPLAY (a null
  // handle here, not eglGetDisplay's default display, which needs X or Wayland).
  else if (attempt("surfaceless", get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)))
    return;

  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (!get_display || !query_devices || !has_extension(client, "EGL_EXT_platform_device")) {
    tried.push_back("EGL_EXT_platform_device (not offered)");
  } else {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!query_devices(16, devices, &count) || count == 0) tried.push_back("EGL_EXT_platform_device (no device)");
    for (EGLint i = 0; i < count; ++i)
      if (attempt("device " + std::to_string(i), get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr))) return;
  }

  std::string message = "cannot create an OpenGL 3.3 core context without a display server; tried:";
  for (const std::string& t : tried) message += "\n  - " + t;
  message += client && *client ? "" : "\n  (no EGL client extensions: is an EGL vendor library such as libegl-mesa0 installed?)";
  throw EglUnavailable(message);
}

void EglContext::make_current() const {
  if (eglGetCurrentContext() == m_context) return;
  if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context))
    throw RenderError("eglMakeCurrent failed (" + egl_error() + ")");
}

EglContext::~EglContext() {
  // The display is not terminated: EGL shares one display per platform within a process,
  // and terminating it would break any other context still in use.
  eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(m_display, m_context);
  eglReleaseThread();
}

}  // namespace sinew
