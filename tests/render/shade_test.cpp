// Pictures from depth maps: the depth and normal map encodings, Lambert lighting against its
// formula, and ambient occlusion as a property of shapes (none on planes and ridges, some in a
// valley), the same for any thread count.
#include <gtest/gtest.h>

#include <cmath>

#include "frep/expr/expr.hpp"
#include "frep/render/render3d.hpp"
#include "frep/render/shade.hpp"

namespace frep {
namespace {

Render3DOptions front(int size) {
  Render3DOptions o;
  o.size = size;
  o.view = ViewDirection::Front;
  o.threads = 2;
  return o;
}

TEST(Shade, DepthMapEncodings) {
  Graph g;
  auto x = g.x(), z = g.z();
  // Left half: a solid reaching the front of the volume (cut there); right half: empty.
  const DepthMap map = render3d(Tape::compile(g, max(x, z - 2.0f).id()), front(8));
  ShadeOptions o;
  o.mode = ShadeMode::Depth;
  const Image depth = shade(map, o);
  ASSERT_EQ(depth.channels, 1);
  EXPECT_EQ(depth.at(0, 3), 255) << "front of the volume";
  EXPECT_EQ(depth.at(7, 3), 0) << "no hit";
  o.mode = ShadeMode::Normals;
  const Image normals = shade(map, o);
  ASSERT_EQ(normals.channels, 3);
  EXPECT_EQ(normals.at(0, 3, 0), 128);
  EXPECT_EQ(normals.at(0, 3, 1), 128);
  EXPECT_EQ(normals.at(0, 3, 2), 255);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(normals.at(7, 3, c), o.background[static_cast<std::size_t>(c)]);

  // A plane z = -0.52 facing the viewer: height 1 + 254 * 0.24.
  const DepthMap plane = render3d(Tape::compile(g, (z + 0.52f).id()), front(8));
  o.mode = ShadeMode::Depth;
  EXPECT_EQ(shade(plane, o).at(4, 4), 1 + std::lround(254 * 0.24));
}

TEST(Shade, LambertAgainstItsFormula) {
  Graph g;
  auto z = g.z();
  const DepthMap plane = render3d(Tape::compile(g, z.id()), front(4));  // normal (0, 0, 1)
  ShadeOptions o;
  o.ambient = 0.3f;
  for (Vec3f light : {Vec3f{0, 0, 1}, Vec3f{0, 0.6f, 0.8f}, Vec3f{0, 0, -1}}) {
    o.light = light;
    const Image img = shade(plane, o);
    const double lit = o.ambient + (1 - o.ambient) * std::max(0.0f, light.z);
    for (int c = 0; c < 3; ++c) {
      // The formula in linear light, with sRGB's curve either side.
      auto lin = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
      auto srgb = [](double v) { return v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1 / 2.4) - 0.055; };
      const double want = 255 * srgb(lin(o.colour[static_cast<std::size_t>(c)] / 255.0) * lit);
      EXPECT_NEAR(img.at(2, 2, c), want, 0.6) << "light z " << light.z << " channel " << c;
    }
  }
}

std::vector<float> ao_of(const char* what, int threads) {
  Graph g;
  auto x = g.x(), z = g.z();
  Expr f = z;
  if (std::string(what) == "valley") f = z - abs(x) * 1.5f + 0.5f;  // surface z = 1.5|x| - 0.5
  if (std::string(what) == "ridge") f = z + abs(x) * 1.5f - 0.5f;   // surface z = 0.5 - 1.5|x|
  if (std::string(what) == "tilted") f = z - x * 0.7f;
  Render3DOptions o = front(64);
  o.threads = threads;
  return ambient_occlusion(render3d(Tape::compile(g, f.id()), o), 0.1f, threads);
}

TEST(Shade, AmbientOcclusionOfPlanesRidgesAndValleys) {
  for (const char* open : {"plane", "ridge", "tilted"}) {
    const std::vector<float> ao = ao_of(open, 2);
    EXPECT_GT(*std::min_element(ao.begin(), ao.end()), 0.97f) << open << " is not occluded";
  }
  const std::vector<float> valley = ao_of("valley", 2);
  // The valley's floor runs down the middle column; its sides see less sky there.
  const float floor = valley[32 * 64 + 32], side = valley[32 * 64 + 60];
  EXPECT_LT(floor, 0.85f);
  EXPECT_GT(side, floor);
  for (int threads : {1, 3}) EXPECT_EQ(ao_of("valley", threads), valley) << threads << " threads";
}

TEST(Shade, ShadedImagesAreTheSameForAnyThreadCount) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Tape t = Tape::compile(g, min(sqrt(square(x) + square(y) + square(z)) - 0.5f, y + 0.4f).id());
  Render3DOptions ro = front(48);
  ro.view = ViewDirection::Iso;
  ShadeOptions so;
  so.ambient_occlusion = true;
  Image ref;
  for (int threads : {1, 2, 3}) {
    ro.threads = so.threads = threads;
    const Image img = shade(render3d(t, ro), so);
    if (threads == 1) ref = img;
    else EXPECT_EQ(img.pixels, ref.pixels) << threads << " threads";
  }
}

}  // namespace
}  // namespace frep
