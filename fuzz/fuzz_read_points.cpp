// libFuzzer entry for the points-file parser (frep eval / frep sdf): InputError is expected;
// anything else is a finding. Parsed columns must have equal lengths.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "frep/error.hpp"
#include "frep/io/points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto p = frep::parse_points_f32(text, "fuzz", size % 2 == 0);
    if (p.y.size() != p.x.size() || p.z.size() != p.x.size()) __builtin_trap();
  } catch (const frep::InputError&) {
  }
  try {
    const auto p = frep::parse_points_f64(text, "fuzz");
    if (p.y.size() != p.x.size() || p.z.size() != p.x.size()) __builtin_trap();
  } catch (const frep::InputError&) {
  }
  return 0;
}
