#pragma once
// Output files are written whole or not at all: to a temporary file in the same folder,
// then renamed over the target.
#include <functional>
#include <ostream>
#include <string>

namespace sinew {

// Calls write(stream) on a temporary file and renames it to `path` when write returns
// normally and the stream is good. Throws std::runtime_error (naming the path) otherwise,
// leaving no file behind.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Creates the folder (and parents). Throws std::runtime_error naming it on failure.
void ensure_directory(const std::string& path);

}  // namespace sinew
