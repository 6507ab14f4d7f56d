// Image files: PNG through stb's writer, and binary PGM.
#include "frep/render/image.hpp"

// stb's PNG writer is compiled in here, with internal linkage, so the library needs no stb
// runtime and cannot clash with a consumer's own copy.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include <filesystem>
#include <string>

#include "frep/error.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep {
namespace {
bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) return false;
  return true;
}
void append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}
}  // namespace

void check_image_path(const std::string& path) {
  if (!ends_with(path, ".png") && !ends_with(path, ".pgm") && !is_device(path))
    throw InputError(path, 0, "unknown image format: use a .png or .pgm file name");
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(path, 0, "cannot write: directory " + parent.string() + " does not exist");
}

void check_image_path(const std::string& path, int channels) {
  check_image_path(path);
  if (channels != 1 && ends_with(path, ".pgm"))
    throw InputError(path, 0, "a .pgm file holds grayscale only: use a .png file name for this colour image");
}

void save_image(const std::string& path, const Image& image) {
  FREP_ASSERT(image.channels == 1 || image.channels == 3, "image channels");
  FREP_ASSERT(image.pixels.size() == static_cast<std::size_t>(image.width) * image.height * image.channels,
              "image size");
  std::string bytes;
  if (ends_with(path, ".png") || (!ends_with(path, ".pgm") && is_device(path))) {
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, image.channels, image.pixels.data(),
                                image.width * image.channels))
      throw InputError(path, 0, "PNG encoding failed");
  } else if (ends_with(path, ".pgm")) {
    if (image.channels != 1)
      throw InputError(path, 0, "a .pgm file holds grayscale only: use a .png file name for this colour image");
    bytes = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
    bytes.append(reinterpret_cast<const char*>(image.pixels.data()), image.pixels.size());
  } else {
    throw InputError(path, 0, "unknown image format: use a .png or .pgm file name");
  }
  write_file_atomically(path, bytes);
}

}  // namespace frep
