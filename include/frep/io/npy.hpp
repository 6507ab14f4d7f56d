// NumPy .npy files (format version 1.0) of float32 ('<f4', little-endian, C order): the
// format `frep sample` writes, which numpy.load, PyTorch and JAX read without conversion.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace frep {

struct NpyArray {
  std::vector<std::size_t> shape;  // C order: the last index varies fastest
  std::vector<float> data;         // product of shape entries
};

// The file's bytes: magic, version 1.0, a header dictionary padded with spaces to a multiple of
// 64 bytes and ended by a newline, then the values as little-endian float32.
std::string npy_bytes(const float* data, const std::vector<std::size_t>& shape);
// Writes atomically (frep::write_file_atomically). Throws InputError if it cannot.
void write_npy(const std::string& path, const float* data, const std::vector<std::size_t>& shape);

// Reads a '<f4' C-order array in format 1.x, 2.x or 3.x (the headers NumPy writes); throws
// InputError naming `name` for anything else or a truncated file.
NpyArray parse_npy(std::string_view bytes, const std::string& name);
NpyArray read_npy(const std::string& path);

}  // namespace frep
