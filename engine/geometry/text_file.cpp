#include "engine/geometry/text_file.hpp"

#include <cstdio>
#include <memory>

#include "engine/core/error.hpp"

namespace sinew {

std::string read_whole_file(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path + ": cannot open file for reading");
  std::string data;
  char chunk[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(chunk, 1, sizeof chunk, f.get())) > 0) data.append(chunk, got);
  if (std::ferror(f.get())) throw InputError(path + ": cannot read file");
  return data;
}

}  // namespace sinew
