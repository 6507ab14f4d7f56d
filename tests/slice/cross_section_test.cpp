// Cross-sections against shapes whose sections are known exactly, and properties on others:
// every vertex on the zero set, rings closed, oriented and non-crossing, results independent of
// the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "frep/eval/evaluators.hpp"
#include "frep/expr/graph.hpp"
#include "frep/model/csg.hpp"
#include "frep/model/shapes.hpp"
#include "frep/model/transform.hpp"
#include "frep/slice/cross_section.hpp"

namespace frep::slice {
namespace {

Tape tape_of(const Field& f) { return Tape::compile(f.graph(), f.id()); }

TEST(CrossSection, SphereGivesItsCircleWithVerticesOnIt) {
  Graph g;
  const Tape t = tape_of(sphere(g, {0, 0, 0}, 5));
  const Region r = cross_section(t, 3, {-6, -6}, {6, 6});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_GT(signed_area(r[0]), 0);  // counter-clockwise
  for (const Point2& p : r[0]) EXPECT_NEAR(std::hypot(p.x, p.y), 4, 1e-4);
  // Chords within the tolerance: the polygon's area is the circle's to within its perimeter times it.
  EXPECT_NEAR(area(r), M_PI * 16, 2 * M_PI * 4 * 0.0006);
}

TEST(CrossSection, BoxKeepsItsExactCorners) {
  Graph g;
  const Tape t = tape_of(box(g, {-2.013, -1.007, -1}, {2.019, 1.003, 1}));
  const Region r = cross_section(t, 0.1, {-3, -3}, {3, 3});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NEAR(area(r), 4.032 * 2.01, 1e-5);
  const Point2 corners[] = {{-2.013, -1.007}, {2.019, -1.007}, {2.019, 1.003}, {-2.013, 1.003}};
  for (const Point2& c : corners) {
    double best = 1e9;
    for (const Point2& p : r[0]) best = std::min(best, std::hypot(p.x - c.x, p.y - c.y));
    EXPECT_LT(best, 1e-5) << "corner " << c.x << ", " << c.y;
  }
}

TEST(CrossSection, HolesRunClockwise) {
  Graph g;
  const Tape t = tape_of(subtract(box(g, {-3, -3, -1}, {3, 3, 1}), sphere(g, {0, 0, 0}, 2)));
  const Region r = cross_section(t, 0, {-4, -4}, {4, 4});
  ASSERT_EQ(r.size(), 2u);
  int outer = 0, holes = 0;
  for (const Ring& ring : r) (signed_area(ring) > 0 ? outer : holes)++;
  EXPECT_EQ(outer, 1);
  EXPECT_EQ(holes, 1);
  EXPECT_NEAR(area(r), 36 - M_PI * 4, 0.01);
}

TEST(CrossSection, ShapeReachingTheRegionIsClosedAtItsBorder) {
  Graph g;
  const Tape t = tape_of(box(g, {-10, -1, -1}, {10, 1, 1}));
  const Region r = cross_section(t, 0, {-2, -2}, {2, 2});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NEAR(area(r), 8, 1e-6);  // cut at the region: its width times the box's
}

TEST(CrossSection, SameRingsOnOneThreadAndOnTwo) {
  Graph g;
  const Field f = unite(sphere(g, {0.3, 0, 0}, 1.1), subtract(box(g, {-1, -1, -1}, {0.7, 1.2, 1}), sphere(g, {-0.5, 0.5, 0}, 0.4)));
  const Tape t = tape_of(f);
  CrossSectionOptions one, two;
  one.threads = 1;
  two.threads = 2;
  one.cell = two.cell = 0.01;
  const Region a = cross_section(t, 0.2, {-2, -2}, {2, 2}, one), b = cross_section(t, 0.2, {-2, -2}, {2, 2}, two);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].size(), b[i].size());
    for (std::size_t k = 0; k < a[i].size(); ++k) {
      EXPECT_EQ(a[i][k].x, b[i][k].x);
      EXPECT_EQ(a[i][k].y, b[i][k].y);
    }
  }
}

// Random unions and differences of spheres and rotated boxes: every vertex on the zero set (or
// a corner of it), the rings non-crossing (normalising them changes nothing), the area close to
// a fine sampling's.
TEST(CrossSection, RandomShapesVerticesOnTheZeroSetAndAreaMatchesSampling) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    Graph g;
    Field f = sphere(g, {u(rng) * 0.3, u(rng) * 0.3, 0}, 0.6 + 0.3 * u(rng));
    for (int k = 0; k < 4; ++k) {
      Field b = rotate(box(g, {-0.4, -0.2, -0.5}, {0.4, 0.2, 0.5}), {0, 0, 1}, 90 * u(rng));
      b = move(b, {u(rng) * 0.7, u(rng) * 0.7, 0});
      Field s = sphere(g, {u(rng) * 0.8, u(rng) * 0.8, u(rng) * 0.2}, 0.25 + 0.1 * u(rng));
      f = k % 2 ? subtract(f, s) : unite(f, b);
    }
    const Tape t = tape_of(f);
    const double z = 0.1 * u(rng);
    CrossSectionOptions o;
    o.cell = 0.02;
    const Region r = cross_section(t, z, {-1.6, -1.6}, {1.6, 1.6}, o);
    PointEvaluator pe;
    for (const Ring& ring : r)
      for (const Point2& p : ring)
        ASSERT_LT(std::fabs(pe.eval(t, static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(z))), 1.05 * o.tolerance)
            << "trial " << trial;
    EXPECT_NEAR(area(normalize(r)), area(r), 1e-9);
    // Area by sampling at 1/400 of the region.
    const int n = 400;
    int in = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (pe.eval(t, static_cast<float>(-1.6 + 3.2 * (i + 0.5) / n), static_cast<float>(-1.6 + 3.2 * (j + 0.5) / n),
                    static_cast<float>(z)) < 0)
          ++in;
    EXPECT_NEAR(area(r), in * (3.2 / n) * (3.2 / n), 0.01) << "trial " << trial;
  }
}

TEST(CrossSection, FindsInsideThinnerThanACellAboveALowestEdge) {
  Graph g;
  // A box standing on an edge along y: just above the edge the section is a strip narrower than a cell.
  const Tape t = tape_of(rotate(box(g, {-1, -1, -1}, {1, 1, 1}), {0, 1, 0}, 45));
  CrossSectionOptions o;
  o.cell = 0.1;
  CrossSectioner s(t, {-2, -2}, {2, 2}, o);
  const double bottom = -std::sqrt(2.0);
  EXPECT_FALSE(s.has_inside(bottom - 1e-3));
  EXPECT_TRUE(s.has_inside(bottom + 1e-4));
  EXPECT_TRUE(s.has_inside(0));
}

TEST(CrossSection, RefusesBadRegions) {
  Graph g;
  const Tape t = tape_of(sphere(g, {0, 0, 0}, 1));
  EXPECT_THROW(CrossSectioner(t, {0, 0}, {0, 1}), InputError);
  EXPECT_THROW(CrossSectioner(t, {0, 0}, {NAN, 1}), InputError);
  CrossSectionOptions o;
  o.cell = 1e-9;
  EXPECT_THROW(CrossSectioner(t, {0, 0}, {1, 1}, o), InputError);
}

}  // namespace
}  // namespace frep::slice
