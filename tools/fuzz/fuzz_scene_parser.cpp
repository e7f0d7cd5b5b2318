// libFuzzer target: the scene parser (engine/scene/scene_parser.cpp). The input is the JSON
// text of a scene. Mesh paths resolve against assets/scenes/, so the shipped scenes of the
// seed corpus parse completely. InputError is the expected rejection; anything else that
// escapes (another exception, a crash, a sanitizer report) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.hpp"
#include "engine/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const sinew::SceneDesc scene =
        sinew::parse_scene_text(text, "fuzz.json", SINEW_SOURCE_DIR "/assets/scenes");
    (void)scene.steps_per_frame();
  } catch (const sinew::InputError&) {
  }
  return 0;
}
