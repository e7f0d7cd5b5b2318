// Row flipping, PNG round trips, image differences.
#include <doctest/doctest.h>

#include <filesystem>
#include <stdexcept>
#include <unistd.h>

#include "render/image.hpp"

using namespace sinew;
namespace fs = std::filesystem;

namespace {

Image gradient(int w, int h) {
  Image im{w, h, std::vector<uint8_t>(3 * size_t(w) * h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = &im.rgb[3 * (size_t(y) * w + x)];
      p[0] = uint8_t(10 * x), p[1] = uint8_t(20 * y), p[2] = uint8_t(x + y);
    }
  return im;
}

}  // namespace

TEST_CASE("image: flip_rows reverses the row order and keeps each row intact") {
  const Image a = gradient(5, 3);
  std::vector<uint8_t> flipped(a.rgb.size()), back(a.rgb.size());
  flip_rows(a.rgb.data(), flipped.data(), 5, 3);
  CHECK(flipped[0] == a.pixel(0, 2)[0]);
  CHECK(flipped[1] == a.pixel(0, 2)[1]);
  CHECK(flipped[3 * 5 * 2 + 3 * 4 + 1] == a.pixel(4, 0)[1]);
  flip_rows(flipped.data(), back.data(), 5, 3);
  CHECK(back == a.rgb);
}

TEST_CASE("image: a PNG reads back identical; a PNG in a missing folder fails and leaves nothing") {
  const fs::path dir = fs::temp_directory_path() / ("sinew_image_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const Image a = gradient(7, 4);
  write_png((dir / "a.png").string(), a);
  const Image b = read_png((dir / "a.png").string());
  CHECK(b.width == 7);
  CHECK(b.height == 4);
  CHECK(b.rgb == a.rgb);
  CHECK_THROWS_AS(write_png((dir / "missing" / "c.png").string(), a), std::runtime_error);
  CHECK(!fs::exists(dir / "missing"));
  CHECK_THROWS_WITH_AS(read_png((dir / "none.png").string()), doctest::Contains("none.png"), std::runtime_error);
  fs::remove_all(dir);
}

TEST_CASE("image: mean absolute difference is per channel in 0..255 and needs equal sizes") {
  Image a = gradient(4, 4), b = a;
  CHECK(mean_abs_difference(a, b) == 0);
  for (size_t i = 0; i < b.rgb.size(); i += 3) b.rgb[i] = uint8_t(b.rgb[i] + 6);  // red +6 everywhere
  CHECK(mean_abs_difference(a, b) == doctest::Approx(2.0));
  CHECK_THROWS_AS(mean_abs_difference(a, gradient(4, 5)), std::runtime_error);
}
