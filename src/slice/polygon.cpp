// Region operations through Clipper (Debian's libpolyclipping), the only file that includes it.
#include "frep/slice/polygon.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

#include "frep/error.hpp"

namespace frep::slice {
namespace {

namespace cl = ClipperLib;

constexpr double kScale = 1.0 / kPolygonResolution;

cl::cInt to_fixed(double v) { return static_cast<cl::cInt>(std::llround(v * kScale)); }

cl::Path to_path(const Ring& ring) {
  cl::Path p;
  p.reserve(ring.size());
  for (const Point2& q : ring) {
    const cl::IntPoint ip(to_fixed(q.x), to_fixed(q.y));
    if (p.empty() || p.back() != ip) p.push_back(ip);
  }
  return p;
}

cl::Paths to_paths(const Region& region) {
  cl::Paths out;
  out.reserve(region.size());
  for (const Ring& r : region) {
    cl::Path p = to_path(r);
    if (p.size() >= 2) out.push_back(std::move(p));
  }
  return out;
}

Ring from_path(const cl::Path& p) {
  Ring r;
  r.reserve(p.size());
  for (const cl::IntPoint& q : p) r.push_back({static_cast<double>(q.X) / kScale, static_cast<double>(q.Y) / kScale});
  return r;
}

Region from_paths(const cl::Paths& ps) {
  Region out;
  out.reserve(ps.size());
  for (const cl::Path& p : ps)
    if (p.size() >= 3) out.push_back(from_path(p));
  return out;
}

Region boolean(cl::ClipType type, const Region& a, const Region& b) {
  cl::Clipper c;
  c.AddPaths(to_paths(a), cl::ptSubject, true);
  c.AddPaths(to_paths(b), cl::ptClip, true);
  cl::Paths out;
  c.Execute(type, out, cl::pftNonZero, cl::pftNonZero);
  return from_paths(out);
}

// Squared distance from p to the segment ab.
double segment_distance2(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  const double ex = a.x + t * dx - p.x, ey = a.y + t * dy - p.y;
  return ex * ex + ey * ey;
}

// Douglas-Peucker on points[first..last] (inclusive), marking the kept ones.
void mark_kept(const std::vector<Point2>& points, std::size_t first, std::size_t last, double tol2,
               std::vector<char>& keep) {
  std::vector<std::pair<std::size_t, std::size_t>> stack{{first, last}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    double worst = -1;
    std::size_t at = i;
    for (std::size_t k = i + 1; k < j; ++k) {
      const double d = segment_distance2(points[k], points[i], points[j]);
      if (d > worst) worst = d, at = k;
    }
    if (worst > tol2) {
      keep[at] = 1;
      stack.push_back({i, at});
      stack.push_back({at, j});
    }
  }
}

void add_islands(const cl::PolyNode& outer, std::vector<Region>& out) {
  Region island{from_path(outer.Contour)};
  for (const cl::PolyNode* hole : outer.Childs) {
    island.push_back(from_path(hole->Contour));
    for (const cl::PolyNode* inner : hole->Childs) add_islands(*inner, out);
  }
  out.push_back(std::move(island));
}

}  // namespace

double signed_area(const Ring& ring) {
  double a = 0;
  const std::size_t n = ring.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) a += (ring[j].x + ring[i].x) * (ring[j].y - ring[i].y);
  return n < 3 ? 0 : -a / 2;
}

double area(const Region& region) {
  double a = 0;
  for (const Ring& r : region) a += signed_area(r);
  return a;
}

double length(const Ring& ring, bool closed) {
  double s = 0;
  for (std::size_t i = 1; i < ring.size(); ++i) s += std::hypot(ring[i].x - ring[i - 1].x, ring[i].y - ring[i - 1].y);
  if (closed && ring.size() > 2) s += std::hypot(ring.front().x - ring.back().x, ring.front().y - ring.back().y);
  return s;
}

Region offset(const Region& region, double delta, double arc_tolerance, Join join) {
  FREP_ASSERT(arc_tolerance > 0, "arc tolerance must be positive");
  if (region.empty()) return {};
  cl::ClipperOffset co(8.0, std::max(arc_tolerance * kScale, 0.25));
  co.AddPaths(to_paths(region), join == Join::Miter ? cl::jtMiter : cl::jtRound, cl::etClosedPolygon);
  cl::Paths out;
  co.Execute(out, delta * kScale);
  return from_paths(out);
}

Region unite(const Region& a, const Region& b) { return boolean(cl::ctUnion, a, b); }
Region intersect(const Region& a, const Region& b) { return boolean(cl::ctIntersection, a, b); }
Region subtract(const Region& a, const Region& b) { return boolean(cl::ctDifference, a, b); }
Region normalize(const Region& rings) { return boolean(cl::ctUnion, rings, {}); }

std::vector<Polyline> clip(const std::vector<Polyline>& lines, const Region& region) {
  if (lines.empty() || region.empty()) return {};
  cl::Clipper c;
  for (const Polyline& l : lines) {
    const cl::Path p = to_path(l);
    if (p.size() >= 2) c.AddPath(p, cl::ptSubject, false);
  }
  c.AddPaths(to_paths(region), cl::ptClip, true);
  cl::PolyTree tree;
  c.Execute(cl::ctIntersection, tree, cl::pftNonZero, cl::pftNonZero);
  cl::Paths open;
  cl::OpenPathsFromPolyTree(tree, open);
  std::vector<Polyline> out;
  out.reserve(open.size());
  for (const cl::Path& p : open)
    if (p.size() >= 2) out.push_back(from_path(p));
  return out;
}

std::vector<Region> islands(const Region& region) {
  cl::Clipper c;
  c.AddPaths(to_paths(region), cl::ptSubject, true);
  cl::PolyTree tree;
  c.Execute(cl::ctUnion, tree, cl::pftNonZero, cl::pftNonZero);
  std::vector<Region> out;
  for (const cl::PolyNode* outer : tree.Childs) add_islands(*outer, out);
  return out;
}

Ring simplify(const Ring& ring, double tolerance, bool closed) {
  const std::size_t n = ring.size();
  if (n < 4 || !(tolerance > 0)) return ring;
  std::vector<char> keep(n, 0);
  const double tol2 = tolerance * tolerance;
  if (!closed) {
    keep[0] = keep[n - 1] = 1;
    mark_kept(ring, 0, n - 1, tol2, keep);
  } else {
    // Split the ring at its first point and the point farthest from it.
    std::size_t far = 0;
    double best = -1;
    for (std::size_t k = 1; k < n; ++k) {
      const double d = (ring[k].x - ring[0].x) * (ring[k].x - ring[0].x) + (ring[k].y - ring[0].y) * (ring[k].y - ring[0].y);
      if (d > best) best = d, far = k;
    }
    keep[0] = keep[far] = 1;
    mark_kept(ring, 0, far, tol2, keep);
    std::vector<Point2> tail(ring.begin() + static_cast<std::ptrdiff_t>(far), ring.end());
    tail.push_back(ring[0]);
    std::vector<char> tail_keep(tail.size(), 0);
    mark_kept(tail, 0, tail.size() - 1, tol2, tail_keep);
    for (std::size_t k = 1; k + 1 < tail.size(); ++k)
      if (tail_keep[k]) keep[far + k] = 1;
  }
  Ring out;
  for (std::size_t k = 0; k < n; ++k)
    if (keep[k]) out.push_back(ring[k]);
  return out;
}

bool bounds(const Region& region, Point2& lo, Point2& hi) {
  bool any = false;
  for (const Ring& r : region)
    for (const Point2& p : r) {
      if (!any) lo = hi = p, any = true;
      lo.x = std::min(lo.x, p.x), lo.y = std::min(lo.y, p.y);
      hi.x = std::max(hi.x, p.x), hi.y = std::max(hi.y, p.y);
    }
  return any;
}

}  // namespace frep::slice
