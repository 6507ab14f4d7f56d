// 8-bit grayscale images and writing them as PNG or PGM.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace frep {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // row-major, top row first, 0 = black, 255 = white

  std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

// Writes atomically; the format comes from the extension (.png or .pgm). Throws InputError for
// an unknown extension or a write failure.
void save_image(const std::string& path, const Image& image);

// Throws InputError unless `path` has a supported extension and its directory exists: lets a
// command fail before long work rather than after it.
void check_image_path(const std::string& path);

}  // namespace frep
