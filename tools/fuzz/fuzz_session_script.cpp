// libFuzzer target: the session-script parser (ui/session_script.cpp). The input is the JSON
// text of a script; InputError is the expected rejection, anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/core/error.hpp"
#include "ui/session_script.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)sinew::parse_session_text(text, "fuzz.json", SINEW_SOURCE_DIR "/assets/sessions");
  } catch (const sinew::InputError&) {
  }
  return 0;
}
