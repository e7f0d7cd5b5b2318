// libFuzzer target: the Wavefront OBJ reader (engine/geometry/obj_reader.hpp). The input is
// the file. InputError is the expected rejection; anything else is a finding.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/geometry/obj_reader.hpp"
#include "tools/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      sinew::fuzz::write_file("input.obj", reinterpret_cast<const char*>(data), size);
  try {
    (void)sinew::read_obj(path);
  } catch (const sinew::InputError&) {
  }
  return 0;
}
