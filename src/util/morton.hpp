// Morton (Z-order) codes: interleaving the bits of three 21-bit cell indices gives a 63-bit key
// whose sort order keeps points that are near in space near in the list (spatially balanced
// trees in the converter, cache-friendly orders in the point-cloud evaluator and the sampler).
// Private to the library (not installed).
#pragma once

#include <cstdint>

namespace frep {

// The low 21 bits of v moved to every third bit (bit i to bit 3 i).
constexpr std::uint64_t morton_spread(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// Largest cell index per axis.
inline constexpr double kMortonCells = 2097151.0;  // 2^21 - 1

static_assert(morton_spread(0x1fffff) == 0x1249249249249249ull);
static_assert(morton_spread(0b101) == 0b1000001);

}  // namespace frep
