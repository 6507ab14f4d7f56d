// Tool paths measured from outside: walls at their exact offsets, no two lines overlapping, no
// spot of a region farther than a line width from every line, infill at its density.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "frep/slice/toolpath.hpp"

namespace frep::slice {
namespace {

Region rect(double x0, double y0, double x1, double y1) { return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

double segment_distance(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0;
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

double path_distance(Point2 p, const ToolPath& path) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = path.points.size();
  for (std::size_t k = 0; k + 1 < n + (path.closed ? 1 : 0); ++k)
    best = std::min(best, segment_distance(p, path.points[k], path.points[(k + 1) % n]));
  return best;
}

bool inside(const Region& r, Point2 p) {
  int wind = 0;
  for (const Ring& ring : r)
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Point2 a = ring[j], b = ring[i];
      if ((a.y <= p.y) != (b.y <= p.y)) {
        const double x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
        if (x > p.x) wind += b.y > a.y ? 1 : -1;
      }
    }
  return wind != 0;
}

double boundary_distance(const Region& r, Point2 p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Ring& ring : r)
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) best = std::min(best, segment_distance(p, ring[j], ring[i]));
  return best;
}

// Samples the region on a grid: the most lines covering one point (a point counts as covered by
// a line when it is within w/2 - margin of its centre) and the widest gap: twice the largest
// radius of a disk in the region that no line covers (the distance from a point to the nearest
// line's side or to the region's boundary, whichever is nearer).
void coverage(const Region& region, const std::vector<ToolPath>& paths, double w, int& most, double& farthest,
              Point2* where = nullptr) {
  Point2 lo, hi;
  ASSERT_TRUE(bounds(region, lo, hi));
  most = 0;
  farthest = 0;
  const double step = w / 7;
  for (double y = lo.y + step / 2; y < hi.y; y += step)
    for (double x = lo.x + step / 2; x < hi.x; x += step) {
      if (!inside(region, {x, y})) continue;
      int covered = 0;
      double nearest = std::numeric_limits<double>::infinity();
      for (const ToolPath& p : paths) {
        const double d = path_distance({x, y}, p);
        nearest = std::min(nearest, d - w / 2);
        if (d < w / 2 - 0.03 * w) ++covered;
      }
      nearest = 2 * std::min(nearest, boundary_distance(region, {x, y}));
      most = std::max(most, covered);
      if (nearest > farthest && where) *where = {x, y};
      farthest = std::max(farthest, nearest);
    }
}

TEST(Toolpath, WallsAreExactOffsetsWithSharpCorners) {
  PrintSettings s;
  const Region square = rect(0, 0, 10, 10);
  const std::vector<ToolPath> ws = walls(square, s);
  ASSERT_EQ(ws.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(ws[static_cast<std::size_t>(k)].role, k == 0 ? PathRole::WallOuter : PathRole::WallInner);
    const double d = (k + 0.5) * s.line_width;
    for (const Point2& p : ws[static_cast<std::size_t>(k)].points) {
      const double edge = std::min({p.x, p.y, 10 - p.x, 10 - p.y});
      EXPECT_NEAR(edge, d, 2e-6);
    }
    EXPECT_EQ(ws[static_cast<std::size_t>(k)].points.size(), 4u);  // the corners stay sharp
  }
}

TEST(Toolpath, RoundHolesGetArcsAtTheirDistance) {
  PrintSettings s;
  Ring hole;
  for (int i = 0; i < 720; ++i) hole.push_back({5 + 2 * std::cos(-i * M_PI / 360), 5 + 2 * std::sin(-i * M_PI / 360)});
  Region part = rect(0, 0, 10, 10);
  part.push_back(hole);
  for (const ToolPath& p : walls(part, s))
    for (const Point2& q : p.points) {
      const double d = std::min({q.x, q.y, 10 - q.x, 10 - q.y, std::hypot(q.x - 5, q.y - 5) - 2});
      const bool outer = p.role == PathRole::WallOuter;
      EXPECT_NEAR(d, (outer ? 0.5 : 1.5) * s.line_width, 1e-3);
    }
}

// A comb of teeth from half a line to five lines wide: every width gets what fits, no two walls
// overlap, and with full infill no gap is wider than a line.
TEST(Toolpath, ThinWallsGetWhatFitsWithoutOverlapsOrWideGaps) {
  PrintSettings s;
  const double w = s.line_width;
  Region comb = rect(0, 0, 40, 3);
  double x = 1;
  for (double width : {0.5, 0.9, 1.2, 1.5, 1.9, 2.3, 2.7, 3.1, 3.5, 4.2, 5.0}) {
    comb = unite(comb, rect(x, 2.9, x + width * w, 12));
    x += width * w + 1.5;
  }
  s.perimeters = 3;
  s.infill = 0;
  int most = 0;
  double widest = 0;
  Point2 at;
  coverage(comb, plan_layer(3, 0.8, 0.7, comb, {}, s).paths, w, most, widest, &at);
  EXPECT_LE(most, 1) << "walls overlap at " << at.x << ", " << at.y;
  s.infill = 100;
  coverage(comb, plan_layer(3, 0.8, 0.7, comb, {}, s).paths, w, most, widest, &at);
  EXPECT_LE(widest, w * 1.02) << "a gap wider than a line at " << at.x << ", " << at.y;
}

TEST(Toolpath, LinesAtTheDensityAsked) {
  const Region r = rect(0, 0, 20, 20);
  const std::vector<Polyline> lines = line_fill(r, 2, 0);
  double total = 0;
  for (const Polyline& l : lines) total += length(l, false);
  EXPECT_NEAR(total, 20 * 20 / 2.0, 20.01);  // one 20 mm line per 2 mm, give or take one
  for (const Polyline& l : lines)
    for (const Point2& p : l) EXPECT_TRUE(p.x >= -1e-6 && p.x <= 20 + 1e-6 && p.y >= -1e-6 && p.y <= 20 + 1e-6);
}

TEST(Toolpath, SolidWhereTheLayersAroundDoNotCover) {
  const Region big = rect(0, 0, 10, 10), small = rect(2, 2, 8, 8);
  // The layer above is smaller: its uncovered rim is under a top surface.
  const Region solid = solid_region(big, {&small, &small}, {&big, &big});
  EXPECT_NEAR(area(solid), 100 - 36, 1e-6);
  // Nothing near a surface in the middle of a prism.
  EXPECT_NEAR(area(solid_region(big, {&big, &big}, {&big, &big})), 0, 1e-9);
  // Beyond the part (no layer there): all solid.
  EXPECT_NEAR(area(solid_region(big, {&big, nullptr}, {&big, &big})), 100, 1e-6);
}

TEST(Toolpath, FullInfillLeavesNoGapWiderThanALine) {
  PrintSettings s;
  s.infill = 100;
  Region part = rect(0, 0, 12, 9);
  part.push_back({{4, 3}, {4, 6}, {8, 6}, {8, 3}});  // a clockwise hole
  const LayerPlan plan = plan_layer(1, 0.4, 0.3, part, {}, s);
  int most = 0;
  double farthest = 0;
  coverage(part, plan.paths, s.line_width, most, farthest);
  EXPECT_LE(farthest, s.line_width * 1.02);
}

}  // namespace
}  // namespace frep::slice
