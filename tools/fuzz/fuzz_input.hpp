#pragma once
// Shared by the libFuzzer targets of tools/fuzz/: the readers take file paths, so each input
// is written to a file in a directory private to the process (made on first use, removed at
// exit) and read back from there.
#include <stdlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace sinew::fuzz {

inline const std::filesystem::path& temp_dir() {
  // Never destroyed: the exit handler below still needs it.
  static const std::filesystem::path* dir = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "sinew_fuzz_XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("fuzz: cannot make a temp dir");
    auto* made = new std::filesystem::path(pattern);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(temp_dir(), ec);
    });
    return made;
  }();
  return *dir;
}

// Writes `size` bytes to TEMP/name (replacing it) and returns the path.
inline std::string write_file(const std::string& name, const char* data, std::size_t size) {
  const std::string path = (temp_dir() / name).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("fuzz: cannot write " + path);
  if (size > 0) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

inline void remove_file(const std::string& name) {
  std::error_code ec;
  std::filesystem::remove(temp_dir() / name, ec);
}

}  // namespace sinew::fuzz
