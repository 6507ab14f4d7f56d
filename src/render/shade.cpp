// Shading a depth map: Lambert plus ambient, height and normal maps, and a horizon-based ambient
// occlusion estimate computed from the depth map (screen space).
#include "frep/render/shade.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "frep/error.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep {
namespace {

// sRGB <-> linear light (the standard piecewise curve), so that lighting adds up physically.
float to_linear(std::uint8_t c) {
  const float v = c / 255.0f;
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}
std::uint8_t to_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  const float s = v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(std::lround(s * 255));
}
std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255)); }

}  // namespace

std::vector<float> ambient_occlusion(const DepthMap& map, float radius, int threads) {
  const int W = map.width(), H = map.height();
  std::vector<float> ao(map.depth.size(), 1.0f);
  const double pixel = 2 * map.camera.half_u / W;  // model units per pixel
  const double reach = std::max(2.0, static_cast<double>(radius) * std::max(W, H));
  constexpr int kDirs = 8, kSteps = 8;
  double dx[kDirs], dy[kDirs];
  for (int d = 0; d < kDirs; ++d) {
    const double a = 2 * std::numbers::pi * (d + 0.5) / kDirs;  // off the pixel axes, so no direction is special
    dx[d] = std::cos(a);
    dy[d] = std::sin(a);
  }
  double dist[kSteps];
  for (int j = 0; j < kSteps; ++j) dist[j] = reach * std::pow((j + 1.0) / kSteps, 1.5);  // denser nearby
  parallel_for_ranges(threads, static_cast<std::size_t>(H), 8, [&](int, std::size_t r0, std::size_t r1) {
    for (int y = static_cast<int>(r0); y < static_cast<int>(r1); ++y)
      for (int x = 0; x < W; ++x) {
        const std::size_t p = map.index(x, y);
        if (!map.hit(x, y)) continue;
        const float h0 = map.depth[p];
        const Vec3f n = map.normal[p];
        double occlusion = 0;
        for (int d = 0; d < kDirs; ++d) {
          // Horizon-based: walking away from p, each sample q that rises higher above p's tangent
          // plane than the ones before hides the sky between the two elevations. The elevation
          // is measured from the actual (rounded) pixel offset, so the tangent plane itself
          // never occludes.
          double horizon = 0;  // sine of the highest elevation so far
          for (int j = 0; j < kSteps; ++j) {
            const int ox = static_cast<int>(std::lround(dx[d] * dist[j]));
            const int oy = static_cast<int>(std::lround(dy[d] * dist[j]));
            const int qx = x + ox, qy = y + oy;
            if ((ox == 0 && oy == 0) || qx < 0 || qy < 0 || qx >= W || qy >= H || !map.hit(qx, qy)) continue;
            // From p to q in view coordinates (image rows grow downward, v upward).
            const double vu = ox * pixel, vv = -oy * pixel, vw = map.depth[map.index(qx, qy)] - h0;
            const double elevation = (n.x * vu + n.y * vv + n.z * vw) / std::sqrt(vu * vu + vv * vv + vw * vw);
            if (elevation <= horizon) continue;
            const double falloff = 1 - (dist[j] / reach) * (dist[j] / reach);
            occlusion += falloff * (elevation - horizon);
            horizon = elevation;
          }
        }
        ao[p] = static_cast<float>(std::clamp(1 - occlusion / kDirs, 0.0, 1.0));
      }
  });
  return ao;
}

Image shade(const DepthMap& map, const ShadeOptions& o) {
  const int W = map.width(), H = map.height();
  FREP_ASSERT(map.depth.size() == static_cast<std::size_t>(W) * H && map.normal.size() == map.depth.size(), "depth map size");
  Image img;
  img.width = W;
  img.height = H;
  img.channels = o.mode == ShadeMode::Depth ? 1 : 3;
  img.pixels.assign(static_cast<std::size_t>(W) * H * img.channels, 0);
  const std::size_t count = map.depth.size();
  if (o.mode == ShadeMode::Depth) {
    const double front = map.camera.half_w, span = 2 * map.camera.half_w;
    for (std::size_t p = 0; p < count; ++p) {
      const float w = map.depth[p];
      if (w != w) continue;
      img.pixels[p] = static_cast<std::uint8_t>(1 + std::lround(254 * std::clamp(1 - (front - w) / span, 0.0, 1.0)));
    }
    return img;
  }
  std::vector<float> ao;
  if (o.mode == ShadeMode::Shaded && o.ambient_occlusion && o.ao_strength > 0)
    ao = ambient_occlusion(map, o.ao_radius, o.threads);
  Vec3f l = o.light;
  const float len = std::sqrt(l.x * l.x + l.y * l.y + l.z * l.z);
  l = len > 0 ? l / len : Vec3f{0, 0, 1};
  const float albedo[3] = {to_linear(o.colour[0]), to_linear(o.colour[1]), to_linear(o.colour[2])};
  const float ambient = std::clamp(o.ambient, 0.0f, 1.0f);
  for (std::size_t p = 0; p < count; ++p) {
    std::uint8_t* px = &img.pixels[p * 3];
    if (map.depth[p] != map.depth[p]) {
      std::copy(o.background.begin(), o.background.end(), px);
      continue;
    }
    const Vec3f n = map.normal[p];
    if (o.mode == ShadeMode::Normals) {
      px[0] = to_byte((n.x + 1) / 2);
      px[1] = to_byte((n.y + 1) / 2);
      px[2] = to_byte((n.z + 1) / 2);
      continue;
    }
    const float diffuse = std::max(0.0f, n.x * l.x + n.y * l.y + n.z * l.z);
    float light = ambient + (1 - ambient) * diffuse;
    if (!ao.empty()) light *= 1 - o.ao_strength * (1 - ao[p]);
    for (int c = 0; c < 3; ++c) px[c] = to_srgb(albedo[c] * light);
  }
  return img;
}

}  // namespace frep
