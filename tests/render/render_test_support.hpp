#pragma once
// Shared by the tests that draw: a Renderer, or a clean skip when this machine has no EGL.
#include <doctest/doctest.h>

#include <memory>

#include "render/render_error.hpp"
#include "render/renderer.hpp"

namespace sinew::test {

// nullptr (after a MESSAGE saying why) only when no EGL display / GL 3.3 context can be made;
// any other failure (shader, framebuffer) propagates and fails the test.
inline std::unique_ptr<Renderer> renderer_or_skip(const RenderOptions& options) {
  try {
    return std::make_unique<Renderer>(options);
  } catch (const EglUnavailable& e) {
    MESSAGE("SKIPPED: no EGL on this machine, so nothing can be drawn: " << e.what());
    return nullptr;
  }
}

// A pixel of a body drawn with body_color(0) (orange) under any of the lights we use: red
// dominates clearly, unlike the grey ground, its shadow, or the blue-grey sky.
inline bool is_body_pixel(const uint8_t* p) { return p[0] > 40 && p[0] > 1.4 * p[1] && p[0] > 2.0 * p[2]; }

}  // namespace sinew::test
