#include "render/image.hpp"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cstring>
#include <stdexcept>

#include "engine/io/atomic_file.hpp"

namespace sinew {

void flip_rows(const uint8_t* src, uint8_t* dst, int width, int height) {
  const size_t row = 3 * static_cast<size_t>(width);
  for (int y = 0; y < height; ++y) std::memcpy(dst + row * (height - 1 - y), src + row * y, row);
}

void write_png(const std::string& path, const Image& image) {
  std::string png;
  auto append = [](void* context, void* data, int size) { static_cast<std::string*>(context)->append(static_cast<char*>(data), size); };
  if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, image.rgb.data(), 3 * image.width))
    throw std::runtime_error("cannot encode PNG for '" + path + "'");
  write_file_atomically(path, [&](std::ostream& out) { out.write(png.data(), png.size()); });
}

Image read_png(const std::string& path) {
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  if (!data) throw std::runtime_error("cannot read image '" + path + "': " + stbi_failure_reason());
  Image image{w, h, std::vector<uint8_t>(data, data + 3 * static_cast<size_t>(w) * h)};
  stbi_image_free(data);
  return image;
}

double mean_abs_difference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::runtime_error("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                             " vs " + std::to_string(b.width) + "x" + std::to_string(b.height));
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) sum += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  return a.rgb.empty() ? 0 : sum / a.rgb.size();
}

}  // namespace sinew
