// Slices: values equal the full tape at every pixel center (pruning is exact), the image axes
// follow the documented convention, and the colouring shows inside and outside in two colours,
// thin contour lines where f is a multiple of the spacing and a bold line on f = 0.
#include <gtest/gtest.h>

#include <cmath>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/expr/expr.hpp"
#include "frep/script/load.hpp"
#include "frep/render/slice.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

// The point of pixel (col, row) of a slice.
void point_of(const SliceField& f, const SliceOptions& o, int col, int row, float p[3]) {
  p[o.axis] = o.offset;
  p[slice_right_axis(o.axis)] = f.right[static_cast<std::size_t>(col)];
  p[slice_up_axis(o.axis)] = f.up[static_cast<std::size_t>(row)];
}

TEST(Slice, ValuesEqualTheFullTapeAndGradientsTheFullGradient) {
  FREP_REQUIRE_DATA("bear.vm");
  const Model m = load_expression(test::data_file("bear.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  PointEvaluator pe;
  GradEvaluator ge;
  for (auto [axis, offset] : {std::pair{0, 0.1f}, {1, -0.2f}, {2, 0.3f}}) {
    for (int threads : {1, 2, 3}) {
      SliceOptions o;
      o.size = 50;
      o.axis = axis;
      o.offset = offset;
      o.threads = threads;
      o.tiles = threads == 3 ? std::vector<int>{7, 3} : std::vector<int>{16, 4};
      o.bounds = Box3{{-1, -0.9, -0.8}, {1.1, 1, 0.8}};
      const SliceField f = SliceRenderer(o).field(t);
      int bad = 0;
      for (int row = 0; row < f.height; ++row)
        for (int col = 0; col < f.width; ++col) {
          float p[3];
          point_of(f, o, col, row, p);
          const std::size_t i = static_cast<std::size_t>(row) * f.width + col;
          const Grad gr = ge.eval(t, p[0], p[1], p[2]);
          const float d[3] = {gr.dx, gr.dy, gr.dz};
          const float slope = std::hypot(d[slice_right_axis(axis)], d[slice_up_axis(axis)]);
          if (!test::same_value(f.value[i], pe.eval(t, p[0], p[1], p[2])) ||
              !(std::fabs(f.slope[i] - slope) <= 1e-5f * std::max(1.0f, slope)))
            ++bad;
        }
      EXPECT_EQ(bad, 0) << "axis " << axis << " threads " << threads;
    }
  }
}

TEST(Slice, AxesAndPixelCenters) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  const Tape t = Tape::compile(g, (x + y * 2.0f + z * 4.0f).id());
  for (int axis : {0, 1, 2}) {
    SliceOptions o;
    o.size = 20;
    o.axis = axis;
    o.offset = 0.5f;
    o.bounds = Box3{{-1, -2, -3}, {1, 2, 3}};
    const SliceField f = SliceRenderer(o).field(t);
    const int ra = slice_right_axis(axis), ua = slice_up_axis(axis);
    EXPECT_NE(ra, axis);
    EXPECT_NE(ua, axis);
    EXPECT_LT(ra, ua) << "the right axis comes first in x, y, z";
    // The longer side has 20 pixels, square pixels, centered on the bounds.
    const double er = o.bounds.size()[ra], eu = o.bounds.size()[ua];
    EXPECT_EQ(std::max(f.width, f.height), 20);
    EXPECT_NEAR(f.pixel, std::max(er, eu) / 20, 1e-12);
    EXPECT_NEAR(f.right.front(), o.bounds.lo[ra] + (f.width * f.pixel - er) / -2 + f.pixel / 2, 1e-6);
    EXPECT_NEAR(f.up.front(), o.bounds.hi[ua] + (f.height * f.pixel - eu) / 2 - f.pixel / 2, 1e-6) << "top row first";
    EXPECT_GT(f.up.front(), f.up.back());
    EXPECT_LT(f.right.front(), f.right.back());
    const float coef[3] = {1, 2, 4};
    for (int row = 0; row < f.height; row += 3)
      for (int col = 0; col < f.width; col += 3) {
        float p[3];
        point_of(f, o, col, row, p);
        EXPECT_FLOAT_EQ(f.value[static_cast<std::size_t>(row) * f.width + col], p[0] + 2 * p[1] + 4 * p[2]);
        EXPECT_FLOAT_EQ(f.slope[static_cast<std::size_t>(row) * f.width + col], std::hypot(coef[ra], coef[ua]));
      }
  }
}

TEST(Slice, DefaultContourSpacing) {
  EXPECT_DOUBLE_EQ(default_contour_spacing(2), 0.2);
  EXPECT_DOUBLE_EQ(default_contour_spacing(10), 1);
  EXPECT_DOUBLE_EQ(default_contour_spacing(3), 0.2);
  EXPECT_DOUBLE_EQ(default_contour_spacing(6), 0.5);
  EXPECT_NEAR(default_contour_spacing(0.05), 0.005, 1e-15);
}

struct Rgb {
  int r, g, b;
};
Rgb at(const Image& img, int x, int y) { return {img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)}; }
bool whiteish(Rgb c) { return c.r > 200 && c.g > 200 && c.b > 200; }

// f = s (x - 0.255) on z = 0 over [-1, 1]^2 at 200 pixels: pixel i has x = -0.995 + 0.01 i, so
// f = 0 on column 125, and f = +-0.2 on columns 125 +- 20 / s.
Image plane_picture(float s, double contour) {
  Graph g;
  const Tape t = Tape::compile(g, ((g.x() - 0.255f) * s).id());
  SliceOptions o;
  o.size = 200;
  o.contour = contour;
  return SliceRenderer(o).render(t);
}

TEST(Slice, InsideOutsideContoursAndTheBoldZeroLine) {
  for (float s : {1.0f, 2.0f}) {
    const Image img = plane_picture(s, 0.2);
    ASSERT_EQ(img.channels, 3);
    const int zero = 125, step = static_cast<int>(std::lround(20 / s));
    for (int y : {0, 77, 199}) {
      // Inside (left, f < 0) blue, outside red-orange, away from the lines.
      for (int x = 0; x < 200; ++x) {
        if (std::abs(x - zero) % step <= 2 || std::abs(x - zero) % step >= step - 2) continue;
        const Rgb c = at(img, x, y);
        if (x < zero) EXPECT_GT(c.b, c.r + 60) << "inside at column " << x;
        else EXPECT_GT(c.r, c.b + 60) << "outside at column " << x;
      }
      // The zero line: white, at least 3 pixels wide; none elsewhere.
      int white = 0;
      for (int x = 0; x < 200; ++x) {
        if (whiteish(at(img, x, y))) {
          ++white;
          EXPECT_LE(std::abs(x - zero), 2) << "white away from f = 0 at column " << x;
        }
      }
      EXPECT_GE(white, 3);
      EXPECT_TRUE(whiteish(at(img, zero, y)));
      // Contour lines where f is a multiple of 0.2: darker than the band on the line pixel's
      // side (3 pixels away) by the line factor, and darker than the other band too (the
      // shading is flat between lines and steps by less than the line factor across one).
      for (int k = -3; k <= 3; ++k) {
        const int x = zero + k * step;
        if (k == 0 || x < 3 || x > 196) continue;
        const Rgb line = at(img, x, y);
        int matching = 0;
        for (int side : {-3, 3}) {
          const Rgb beside = at(img, x + side, y);
          const double ratio = static_cast<double>(line.r + line.g + line.b) / (beside.r + beside.g + beside.b);
          EXPECT_LT(ratio, 0.8) << "column " << x << " scale " << s;
          matching += std::fabs(ratio - SliceColours::line_darkening) < 0.03;
        }
        EXPECT_GE(matching, 1) << "column " << x << " scale " << s;
        // Thin: the pixels two away are not darkened (flat band from 2 to 4 pixels away).
        for (int side : {-1, 1}) {
          const Rgb near = at(img, x + 2 * side, y), far = at(img, x + 4 * side, y);
          EXPECT_NEAR(near.r + near.g + near.b, far.r + far.g + far.b, 3) << "column " << x;
        }
      }
    }
  }
  // Lines closer than a few pixels fade out instead of filling the picture.
  const Image dense = plane_picture(1.0f, 0.005);
  const Rgb a = at(dense, 60, 100), b = at(dense, 61, 100), c = at(dense, 62, 100);
  EXPECT_LE(std::abs(a.r - b.r) + std::abs(b.r - c.r), 6);
}

TEST(Slice, NoZeroLineWithoutACrossing) {
  // f = 0.5 + 0.4 sin(1000 x) is never 0, but |f| / |grad f| is a fraction of a pixel: the
  // first-order distance estimate alone would draw the zero line all over the picture.
  Graph g;
  const Tape t = Tape::compile(g, (sin(g.x() * 1000.0f) * 0.4f + 0.5f).id());
  SliceOptions o;
  o.size = 100;
  const Image img = render_slice(t, o);
  int white = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) white += whiteish(at(img, x, y));
  EXPECT_EQ(white, 0);
}

TEST(Slice, NanPixelsAreGray) {
  Graph g;
  const Tape t = Tape::compile(g, sqrt(g.x()).id());  // NaN where x < 0
  SliceOptions o;
  o.size = 20;
  const Image img = render_slice(t, o);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(img.at(2, 10, c), SliceColours::nan[c]);
  EXPECT_NE(img.at(17, 10, 0), SliceColours::nan[0]);
}

TEST(Slice, InvalidOptionsThrow) {
  Graph g;
  const Tape t = Tape::compile(g, g.var_x());
  SliceOptions o;
  o.axis = 3;
  EXPECT_THROW(render_slice(t, o), InputError);
  o.axis = 2;
  o.bounds = Box3{{0, 0, 0}, {0, 1, 1}};
  EXPECT_THROW(render_slice(t, o), InputError);
  o.bounds = Box3{{0, 0, 0}, {1, 1, 0}};  // flat along z: fine for a z slice
  o.size = 8;
  EXPECT_NO_THROW(render_slice(t, o));
  o.contour = -1;
  EXPECT_THROW(render_slice(t, o), InputError);
}

}  // namespace
}  // namespace frep
