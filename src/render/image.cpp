#include "frep/render/image.hpp"

// stb's PNG writer is compiled in here, with internal linkage, so the library needs no stb
// runtime and cannot clash with a consumer's own copy.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include <filesystem>
#include <string>

#include "frep/error.hpp"
#include "frep/io/atomic_file.hpp"

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
  if (!ends_with(path, ".png") && !ends_with(path, ".pgm"))
    throw InputError(path, 0, "unknown image format: use a .png or .pgm file name");
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(path, 0, "cannot write: directory " + parent.string() + " does not exist");
}

void save_image(const std::string& path, const Image& image) {
  FREP_ASSERT(image.pixels.size() == static_cast<std::size_t>(image.width) * image.height, "image size");
  std::string bytes;
  if (ends_with(path, ".png")) {
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 1, image.pixels.data(), image.width))
      throw InputError(path, 0, "PNG encoding failed");
  } else if (ends_with(path, ".pgm")) {
    bytes = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
    bytes.append(reinterpret_cast<const char*>(image.pixels.data()), image.pixels.size());
  } else {
    throw InputError(path, 0, "unknown image format: use a .png or .pgm file name");
  }
  write_file_atomically(path, bytes);
}

}  // namespace frep
