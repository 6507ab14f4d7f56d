// NumPy .npy writer and reader for float32 arrays (format documented in numpy.lib.format).
#include "frep/io/npy.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <ostream>

#include "frep/error.hpp"
#include "frep/util/atomic_file.hpp"

namespace frep {
namespace {

constexpr char kMagic[] = "\x93NUMPY";

std::size_t element_count(const std::vector<std::size_t>& shape) {
  std::size_t n = 1;
  for (std::size_t s : shape) n *= s;
  return n;
}

void append_le32(std::string& out, const float* data, std::size_t n) {
  const std::size_t at = out.size();
  out.resize(at + 4 * n);
  if constexpr (std::endian::native == std::endian::little) {
    if (n) std::memcpy(out.data() + at, data, 4 * n);
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const auto u = std::bit_cast<std::uint32_t>(data[i]);
      for (int b = 0; b < 4; ++b) out[at + 4 * i + b] = static_cast<char>((u >> (8 * b)) & 0xff);
    }
  }
}

}  // namespace

namespace {

// Magic, version, header length and the header dictionary, padded to a multiple of 64 bytes.
std::string npy_header(const std::vector<std::size_t>& shape) {
  // Python tuple syntax: a one-element tuple needs its trailing comma.
  std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < shape.size(); ++i) dict += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) dict += ",";
  dict += "), }";
  // magic (6) + version (2) + header length (2) + dict + padding + '\n', a multiple of 64.
  const std::size_t unpadded = 10 + dict.size() + 1;
  const std::size_t total = (unpadded + 63) / 64 * 64;
  FREP_ASSERT(total - 10 <= 0xffff, "npy header too long for format 1.0");
  dict.append(total - unpadded, ' ');
  dict += '\n';
  std::string out(kMagic, 6);
  out += '\x01';
  out += '\x00';
  const std::size_t hl = dict.size();
  out += static_cast<char>(hl & 0xff);
  out += static_cast<char>(hl >> 8);
  out += dict;
  return out;
}

}  // namespace

std::string npy_bytes(const float* data, const std::vector<std::size_t>& shape) {
  std::string out = npy_header(shape);
  const std::size_t n = element_count(shape);
  out.reserve(out.size() + 4 * n);
  append_le32(out, data, n);
  return out;
}

void write_npy(const std::string& path, const float* data, const std::vector<std::size_t>& shape) {
  // Streamed in pieces: a big grid is not copied whole into memory a second time.
  write_file_atomically(path, [&](std::ostream& os) {
    os << npy_header(shape);
    const std::size_t n = element_count(shape), piece = std::size_t{1} << 20;
    std::string buf;
    for (std::size_t i = 0; i < n; i += piece) {
      buf.clear();
      append_le32(buf, data + i, std::min(piece, n - i));
      os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    }
  });
}

NpyArray parse_npy(std::string_view b, const std::string& name) {
  auto fail = [&](const std::string& m) -> InputError { return InputError(name, 0, "not a float32 .npy file: " + m); };
  if (b.size() < 10 || b.substr(0, 6) != std::string_view(kMagic, 6)) throw fail("no NumPy magic");
  const int major = static_cast<unsigned char>(b[6]);
  std::size_t hl = 0, start = 0;
  if (major == 1) {
    hl = static_cast<unsigned char>(b[8]) | (std::size_t(static_cast<unsigned char>(b[9])) << 8);
    start = 10;
  } else if (major == 2 || major == 3) {
    if (b.size() < 12) throw fail("truncated header");
    for (int i = 0; i < 4; ++i) hl |= std::size_t(static_cast<unsigned char>(b[8 + i])) << (8 * i);
    start = 12;
  } else {
    throw fail("unknown format version " + std::to_string(major));
  }
  if (b.size() < start + hl) throw fail("truncated header");
  const std::string_view h = b.substr(start, hl);
  if (h.find("'descr': '<f4'") == std::string_view::npos) throw fail("dtype is not '<f4'");
  if (h.find("'fortran_order': False") == std::string_view::npos) throw fail("not in C order");
  const std::size_t s = h.find("'shape': (");
  if (s == std::string_view::npos) throw fail("no shape");
  NpyArray a;
  std::size_t i = s + 10;
  while (i < h.size() && h[i] != ')') {
    if (h[i] >= '0' && h[i] <= '9') {
      std::size_t v = 0;
      while (i < h.size() && h[i] >= '0' && h[i] <= '9') v = v * 10 + std::size_t(h[i++] - '0');
      a.shape.push_back(v);
    } else if (h[i] == ',' || h[i] == ' ') {
      ++i;
    } else {
      throw fail("bad shape");
    }
  }
  if (i == h.size()) throw fail("bad shape");
  const std::size_t n = element_count(a.shape);
  const std::size_t at = start + hl;
  if ((b.size() - at) / 4 < n || b.size() - at != 4 * n) throw fail("data size does not match the shape");
  a.data.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    std::uint32_t u = 0;
    for (int j = 0; j < 4; ++j) u |= std::uint32_t(static_cast<unsigned char>(b[at + 4 * k + j])) << (8 * j);
    a.data[k] = std::bit_cast<float>(u);
  }
  return a;
}

NpyArray read_npy(const std::string& path) { return parse_npy(read_file(path), path); }

}  // namespace frep
