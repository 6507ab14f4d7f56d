// 8-bit images, grayscale or RGB, and writing them as PNG or PGM.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace frep {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;                  // 1 = grayscale, 3 = RGB
  std::vector<std::uint8_t> pixels;  // row-major, top row first, `channels` bytes per pixel; 0 = black

  // Channel `c` of pixel (x, y) (for grayscale images, the only one).
  std::uint8_t at(int x, int y, int c = 0) const {
    return pixels[(static_cast<std::size_t>(y) * width + x) * static_cast<std::size_t>(channels) + c];
  }
};

// Writes atomically; the format comes from the extension (.png, or .pgm for grayscale images); a
// device (is_device: /dev/null) gets PNG, written in place.
// Throws InputError for an unknown extension, a colour image as .pgm, or a write failure.
void save_image(const std::string& path, const Image& image);

// Throws InputError unless `path` has a supported extension (or is a device) and its directory exists: lets a
// command fail before long work rather than after it.
void check_image_path(const std::string& path);
// The same for an image of `channels` channels (.pgm holds grayscale only).
void check_image_path(const std::string& path, int channels);

}  // namespace frep
