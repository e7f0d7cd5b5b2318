#pragma once
// Failures of the renderer and of capture (no EGL display, no ffmpeg, ffmpeg failed).
// The message says what was tried and what to install or change.
#include <stdexcept>

namespace sinew {

struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// No EGL display or OpenGL 3.3 core context could be made on this machine (as opposed to a
// bug of ours, such as a shader that does not compile). Tests skip only on this one.
struct EglUnavailable : RenderError {
  using RenderError::RenderError;
};

}  // namespace sinew
