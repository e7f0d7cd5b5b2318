// The headless OpenGL context: what it offers, and several on one thread.
#include <doctest/doctest.h>

#include <memory>
#include <string>

#include "render/egl_context.hpp"
#include "render/render_error.hpp"

using namespace sinew;

TEST_CASE("EGL: a context says which platform it came from and is at least OpenGL 3.3") {
  std::unique_ptr<EglContext> context;
  try {
    context = std::make_unique<EglContext>();
  } catch (const EglUnavailable& e) {
    MESSAGE("SKIPPED: no EGL on this machine: " << e.what());
    return;
  }
  const std::string d = context->description();
  MESSAGE("EGL context: " << d);
  CHECK((d.rfind("surfaceless:", 0) == 0 || d.rfind("device ", 0) == 0));
  const auto colon = d.find(": ");
  REQUIRE(colon != std::string::npos);
  // Version strings start "MAJOR.MINOR"; 3.3 core was asked for, a later one is fine.
  const int major = std::stoi(d.substr(colon + 2)), minor = std::stoi(d.substr(d.find('.', colon) + 1));
  CHECK(major * 10 + minor >= 33);
  // A second context on the same thread can be made and each made current in turn.
  EglContext other;
  CHECK_NOTHROW(context->make_current());
  CHECK_NOTHROW(other.make_current());
}
