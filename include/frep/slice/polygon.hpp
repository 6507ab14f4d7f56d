// Planar regions for slicing: closed rings of points in model units, and the set operations,
// offsets and clipping on them (done by Clipper, in fixed point of 1 nanometre per unit when the
// unit is the millimetre). A region is a list of rings under the nonzero rule: outer boundaries
// run counter-clockwise, holes clockwise, and no two rings cross.
#pragma once

#include <vector>

namespace frep::slice {

struct Point2 {
  double x = 0, y = 0;
};

using Ring = std::vector<Point2>;      // closed: the last point connects back to the first
using Region = std::vector<Ring>;      // the nonzero rule; CCW outer rings, CW holes
using Polyline = std::vector<Point2>;  // open

// Twice the signed area enclosed (positive for counter-clockwise rings) divided by two: the area.
double signed_area(const Ring& ring);
// The area of a region (outer rings minus holes).
double area(const Region& region);
// Total length of a ring (closed) or a polyline (open).
double length(const Ring& ring, bool closed);

// Fixed-point resolution of the operations below: coordinates are rounded to this step.
inline constexpr double kPolygonResolution = 1e-6;

// How offset() treats the corners that open up on the growing side.
enum class Join {
  Round,  // arcs: the exact offset (every point at |delta| from the region)
  Miter,  // the shifted edges extended until they meet (up to 8 |delta| from the corner), so a
          // sharp corner stays sharp: what growing back a shrunk region needs to restore it
};

// The region grown by `delta` (shrunk if negative). With Join::Round it is the exact offset:
// every point whose distance to the region is at most delta (or, shrinking, every point at least
// -delta inside it); the corners that open up get arcs, each within `arc_tolerance` of the true
// circle, and the other corners stay sharp, as the exact offset has them.
Region offset(const Region& region, double delta, double arc_tolerance, Join join = Join::Round);
// Boolean operations; results are oriented and non-crossing.
Region unite(const Region& a, const Region& b);
Region intersect(const Region& a, const Region& b);
Region subtract(const Region& a, const Region& b);
// Normalises any rings (crossing, either orientation) to a region under the nonzero rule.
Region normalize(const Region& rings);

// The parts of open polylines inside a region.
std::vector<Polyline> clip(const std::vector<Polyline>& lines, const Region& region);

// The connected parts of a region: each an outer ring followed by its holes.
std::vector<Region> islands(const Region& region);

// Drops points closer than `tolerance` to the chord of their neighbours (Douglas-Peucker): the
// result keeps a subset of the points, within `tolerance` of the input everywhere.
Ring simplify(const Ring& ring, double tolerance, bool closed);

// Axis-aligned bounds of the points of a region; false if it has none.
bool bounds(const Region& region, Point2& lo, Point2& hi);

}  // namespace frep::slice
