// The tiled, pruned, multithreaded 2D renderer equals the brute-force reference pixel for pixel,
// whatever the thread count and tile options.
#include <gtest/gtest.h>

#include "frep/error.hpp"
#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "frep/render/render2d.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

std::string first_difference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    return "sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
           std::to_string(b.width) + "x" + std::to_string(b.height);
  int count = 0;
  std::string first;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      if (a.at(x, y) != b.at(x, y)) {
        if (!count) first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " + std::to_string(a.at(x, y)) +
                            " vs " + std::to_string(b.at(x, y));
        ++count;
      }
  return count ? std::to_string(count) + " pixels differ, first " + first : "";
}

std::vector<RenderOptions> option_variants(int size, float z = 0.0f) {
  std::vector<RenderOptions> v;
  for (int threads : {1, 2, 3}) {
    RenderOptions o;
    o.size = size;
    o.threads = threads;
    o.z = z;
    v.push_back(o);
  }
  RenderOptions a;
  a.size = size, a.threads = 2, a.z = z, a.tiles = {64, 8};
  v.push_back(a);
  RenderOptions b;
  b.size = size, b.threads = 3, b.z = z, b.tiles = {100, 10, 1};
  v.push_back(b);
  RenderOptions c;
  c.size = size, c.threads = 0, c.z = z, c.tiles = {size};  // one level: no subdivision
  v.push_back(c);
  return v;
}

void expect_renders_match(const Tape& t, int size, const std::string& what, float z = 0.0f) {
  RenderOptions base;
  base.size = size;
  base.z = z;
  const Image ref = render2d_brute_force(t, base);
  ASSERT_EQ(ref.width, size);
  ASSERT_EQ(ref.pixels.size(), static_cast<std::size_t>(size) * size);
  for (const RenderOptions& o : option_variants(size, z)) {
    const Image img = render2d(t, o);
    const std::string diff = first_difference(img, ref);
    EXPECT_TRUE(diff.empty()) << what << " size " << size << " threads " << o.threads << " tiles "
                              << ::testing::PrintToString(o.tiles) << ": " << diff;
  }
}

Tape load(const std::string& name) {
  const Model m = read_vm(test::data_file(name));
  return Tape::compile(*m.graph, m.root);
}

TEST(Render, Prospero256) {
  FREP_REQUIRE_DATA("prospero.vm");
  expect_renders_match(load("prospero.vm"), 256, "prospero");
}

TEST(Render, Prospero333OddSize) {
  FREP_REQUIRE_DATA("prospero.vm");
  expect_renders_match(load("prospero.vm"), 333, "prospero");
}

TEST(Render, HiAndQuarter) {
  FREP_REQUIRE_DATA("hi.vm");
  FREP_REQUIRE_DATA("quarter.vm");
  for (int size : {256, 101, 1, 2, 17}) {
    expect_renders_match(load("hi.vm"), size, "hi.vm");
    expect_renders_match(load("quarter.vm"), size, "quarter.vm");
  }
}

TEST(Render, ThreeDModelsAtSeveralSlices) {
  FREP_REQUIRE_DATA("bear.vm");
  FREP_REQUIRE_DATA("tanglecube.vm");
  for (float z : {0.0f, 0.3f, -0.55f}) {
    expect_renders_match(load("bear.vm"), 96, "bear.vm", z);
    expect_renders_match(load("tanglecube.vm"), 80, "tanglecube.vm", z * 5);
  }
}

// `count` random 2D expressions over `ops` (all ops if empty), each rendered against brute force;
// with `csg_root`, the root is a min or max (alternately) of two of them.
void expect_random_renders_match(std::uint64_t seed, int count, std::vector<Op> ops, bool csg_root, const std::string& what) {
  std::mt19937_64 rng(seed);
  for (int e = 0; e < count; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.vars = 2;
    opt.max_depth = 4 + e % 4;
    opt.special_const_prob = 0.02;
    opt.const_range = 1.5f;
    opt.ops = ops;
    test::ExprGen gen(g, rng, opt);
    NodeId root = gen.gen();
    if (csg_root) root = g.binary(e % 2 ? Op::Min : Op::Max, root, gen.gen());
    expect_renders_match(Tape::compile(g, root), e % 2 ? 67 : 64, what + " #" + std::to_string(e));
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(Render, RandomTwoDimensionalExpressions) { expect_random_renders_match(81, 80, {}, false, "random expression"); }

// Unions and intersections at the root, as CSG models have: the renderer reads only signs, so it
// simplifies with a root cap of 0 (terms only positive in a tile go), which must not change a pixel.
TEST(Render, RandomUnionsAndIntersections) {
  expect_random_renders_match(
      82, 60, {Op::Min, Op::Max, Op::Min, Op::Max, Op::Add, Op::Sub, Op::Mul, Op::Neg, Op::Abs, Op::Square, Op::Sqrt, Op::Sin},
      true, "random union or intersection");
}

TEST(Render, RendererObjectIsReusableAcrossTapes) {
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape a = Tape::compile(g, (sqrt(square(x) + square(y)) - 0.5f).id());
  const Tape b = Tape::compile(g, max(abs(x) - 0.3f, abs(y) - 0.7f).id());
  RenderOptions o;
  o.size = 120;
  o.threads = 2;
  o.tiles = {32, 8};
  Renderer2D r(o);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(r.render(a).pixels, render2d_brute_force(a, o).pixels);
    EXPECT_EQ(r.render(b).pixels, render2d_brute_force(b, o).pixels);
  }
  EXPECT_EQ(r.options().size, 120);
}

TEST(Render, PixelCentersAndOrientation) {
  // x > 0 is outside (black) on the right half; the top row is y = +1.
  Graph g;
  RenderOptions o;
  o.size = 5;
  const Image right = render2d(Tape::compile(g, g.var_x()), o);
  EXPECT_EQ(right.at(0, 2), 255);
  EXPECT_EQ(right.at(2, 2), 0) << "x = 0 exactly is not negative";
  EXPECT_EQ(right.at(4, 2), 0);
  const Image top = render2d(Tape::compile(g, g.var_y()), o);
  EXPECT_EQ(top.at(2, 0), 0);
  EXPECT_EQ(top.at(2, 4), 255);
  const Image nan = render2d(Tape::compile(g, g.constant(std::numeric_limits<float>::quiet_NaN())), o);
  for (auto p : nan.pixels) EXPECT_EQ(p, 0) << "NaN is not negative";
}

TEST(Render, InvalidOptionsThrow) {
  Graph g;
  const Tape t = Tape::compile(g, g.var_x());
  RenderOptions o;
  o.size = 0;
  EXPECT_THROW(render2d(t, o), InputError);
  EXPECT_THROW(render2d_brute_force(t, o), InputError);
  o.size = 16;
  o.tiles = {};
  EXPECT_THROW(render2d(t, o), InputError);
  o.tiles = {4, 8};
  EXPECT_THROW(render2d(t, o), InputError);
  o.tiles = {8, 0};
  EXPECT_THROW(render2d(t, o), InputError);
}

// Regression (9b2043f): atan(exp(1000 x) - exp(1000 y)) - 5 is NaN where both exponentials
// overflow (x, y > 0.089), so those pixels are black in the brute-force image; the tiled renderer
// must not classify the whole image as inside from the interval [-6.6, -3.4].
TEST(Render, OverflowToInfMinusInfIsNotClassifiedInside) {
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape t = Tape::compile(g, (atan(exp(x * 1000.0f) - exp(y * 1000.0f)) - 5.0f).id());
  expect_renders_match(t, 64, "atan(exp(1000x) - exp(1000y)) - 5");
}

// Regression (see IntervalRegression.DivisorWithZeroAndInfinity), from finite pixel coordinates:
// a = exp(1000 x) + 1 is in [1, inf], b = 1e38 y * 1000 in [-inf, inf] (overflow), and
// atan(a / b) - 5 is NaN where a and b are both infinite (x > 0.089, |y| > 1e-5): black pixels
// in the brute-force image; a known interval there used to make the tiled renderer fill white.
TEST(RenderRegression, InfOverInfFromOverflowIsNotClassifiedInside) {
  Graph g;
  auto x = g.x(), y = g.y();
  const Tape t = Tape::compile(g, (atan((exp(x * 1000.0f) + 1.0f) / (y * 1e38f * 1000.0f)) - 5.0f).id());
  RenderOptions o;
  o.size = 64;
  o.threads = 1;
  const std::string diff = first_difference(render2d(t, o), render2d_brute_force(t, o));
  EXPECT_TRUE(diff.empty()) << diff;
}

}  // namespace
}  // namespace frep
