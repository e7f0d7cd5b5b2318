#pragma once
// An RGB8 image, rows top to bottom, plus PNG I/O and comparison.
#include <cstdint>
#include <string>
#include <vector>

namespace sinew {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 3 * width * height

  const uint8_t* pixel(int x, int y) const { return &rgb[3 * (static_cast<size_t>(y) * width + x)]; }
};

// Copies `height` rows of 3 * width bytes in reverse order (GL's bottom-up <-> top-down).
void flip_rows(const uint8_t* src, uint8_t* dst, int width, int height);

// Written whole or not at all (temporary file, then rename). Throws std::runtime_error.
void write_png(const std::string& path, const Image& image);
// Throws std::runtime_error naming the file if it cannot be read as an image.
Image read_png(const std::string& path);

// Mean of |a - b| over all channels of all pixels, in 0..255. Throws if sizes differ.
double mean_abs_difference(const Image& a, const Image& b);

}  // namespace sinew
