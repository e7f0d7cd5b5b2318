// libFuzzer target: the Gmsh .msh reader (engine/geometry/gmsh_reader.hpp). The input is the
// file. InputError is the expected rejection; anything else is a finding.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/geometry/gmsh_reader.hpp"
#include "tools/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      sinew::fuzz::write_file("input.msh", reinterpret_cast<const char*>(data), size);
  try {
    (void)sinew::read_gmsh(path);
  } catch (const sinew::InputError&) {
  }
  return 0;
}
