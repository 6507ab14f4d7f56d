// Pictures from a depth map (render3d.hpp): lit and shaded, as a height map, or as a normal map,
// with optional ambient occlusion estimated from the depth map itself.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "frep/math/vec.hpp"
#include "frep/render/image.hpp"
#include "frep/render/render3d.hpp"

namespace frep {

enum class ShadeMode {
  Shaded,   // RGB: the surface colour lit by one directional light (Lambert) plus ambient light
  Depth,    // grayscale height map: 255 at the front of the view volume, 1 at its back, 0 = no hit
  Normals,  // RGB normal map: (n + 1) / 2 per channel, n in view coordinates (x right, y up, z toward the viewer)
};

struct ShadeOptions {
  ShadeMode mode = ShadeMode::Shaded;                 // what to draw
  bool ambient_occlusion = false;                     // darken creases and cavities (shaded mode only)
  float ao_radius = 0.03f;                            // occlusion search radius, a fraction of the image's longer side
  float ao_strength = 1.0f;                           // 0 = no darkening, 1 = full horizon-based estimate
  Vec3f light{-0.45f, 0.6f, 0.65f};                   // direction toward the light, view coordinates (normalized when used)
  float ambient = 0.25f;                              // light reaching every point, 0 to 1
  std::array<std::uint8_t, 3> colour{214, 196, 168};  // surface colour (sRGB)
  std::array<std::uint8_t, 3> background{72, 72, 76}; // pixels without a hit (shaded and normals modes)
  int threads = 0;                                    // worker threads for occlusion; 0 = all hardware threads
};

// The picture of `map` (1 channel in depth mode, else 3). Deterministic for any thread count.
Image shade(const DepthMap& map, const ShadeOptions& options = {});

// Per pixel (row-major), the fraction of light not blocked by nearby parts of the depth map:
// horizon-based, 8 directions, within `radius` (a fraction of the image's longer side). 1 where
// nothing blocks and where there is no hit. Uses only depths and normals, so it works for fields
// that are not distances.
std::vector<float> ambient_occlusion(const DepthMap& map, float radius, int threads = 0);

}  // namespace frep
