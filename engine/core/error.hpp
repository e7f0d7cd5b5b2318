#pragma once
// Errors in user input (scene files, meshes, scripts). The message already names the
// file, the line or JSON path, and what was expected; the CLI prints it and exits non-zero.
#include <stdexcept>
#include <string>

namespace sinew {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace sinew
