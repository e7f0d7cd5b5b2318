// libFuzzer target: the TetGen reader (engine/geometry/tetgen_reader.hpp). The input holds
// both files: the .node text, then a line "@ele" and the .ele text. Without that line only
// the .node file is written (the reader must then report the missing .ele). InputError is
// the expected rejection; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "engine/core/error.hpp"
#include "engine/geometry/tetgen_reader.hpp"
#include "tools/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kSeparator = "\n@ele\n";
  const std::size_t at = input.find(kSeparator);
  const std::string_view node = input.substr(0, at);
  const std::string base =
      sinew::fuzz::write_file("input.node", node.data(), node.size());
  if (at == std::string_view::npos) {
    sinew::fuzz::remove_file("input.ele");
  } else {
    const std::string_view ele = input.substr(at + kSeparator.size());
    sinew::fuzz::write_file("input.ele", ele.data(), ele.size());
  }
  try {
    (void)sinew::read_tetgen(base);
  } catch (const sinew::InputError&) {
  }
  return 0;
}
