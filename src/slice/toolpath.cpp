// Walls by erosion and miter dilation: the k-th wall is the boundary of the island eroded by
// k widths and grown back by half a width, which is exactly the (k - 1/2) w offset wherever a
// whole lane fits (sharp corners stay sharp: erosion keeps convex corners sharp and a miter
// dilation keeps them so; concave corners are arcs both ways), and absent where the two sides'
// lanes would overlap. Strips too thin for a lane on each side but at least one line wide get one
// line along them, within half a width of their middle (gap fill), so no gap is wider than a line.
#include "frep/slice/toolpath.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/error.hpp"

namespace frep::slice {
namespace {

// Outlines simplified to this many line widths decide where walls fit and bound the infill.
constexpr double kCoarse = 0.01;

double arc_tolerance(const PrintSettings& s) { return std::min(s.section_tolerance, s.line_width * 0.002); }

// Grows a shrunk region back with its sharp corners kept.
Region dilate_sharp(const Region& r, double delta, const PrintSettings& s) {
  return offset(r, delta, arc_tolerance(s), Join::Miter);
}

double dist2(Point2 a, Point2 b) { return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y); }

// Lines along strips one to two widths wide: the strip shrunk by just under half a width is
// less than a width wide; its boundary, halved between its two ends (or its holes' rings for a
// closed strip), runs within half a width of the strip's middle, and a line there stays in the
// strip.
void gap_fill(const Region& gap, const PrintSettings& s, PathRole role, std::vector<ToolPath>& out) {
  const double w = s.line_width;
  const Region sliver = offset(gap, -0.499 * w, arc_tolerance(s));
  for (const Region& piece : islands(sliver)) {
    if (piece.empty()) continue;
    if (piece.size() > 1) {  // a closed strip: its holes' rings go around
      for (std::size_t k = 1; k < piece.size(); ++k) out.push_back({role, true, piece[k]});
      continue;
    }
    const Ring& r = piece[0];
    if (length(r, true) < 2 * w) continue;  // a speck
    // Its two ends: the point farthest from the first, and the one farthest from that (two
    // sweeps instead of all pairs, which long slivers of lattice parts make costly).
    const auto farthest = [&](std::size_t from) {
      std::size_t at = from;
      for (std::size_t i = 0; i < r.size(); ++i)
        if (dist2(r[i], r[from]) > dist2(r[at], r[from])) at = i;
      return at;
    };
    std::size_t a = farthest(0), b = farthest(a);
    if (a > b) std::swap(a, b);
    Polyline half(r.begin() + static_cast<std::ptrdiff_t>(a), r.begin() + static_cast<std::ptrdiff_t>(b) + 1);
    out.push_back({role, false, std::move(half)});
  }
}

// Rotates a closed path to start nearest `from`; returns its new start.
void start_nearest(ToolPath& p, Point2 from) {
  if (!p.closed || p.points.size() < 2) return;
  std::size_t best = 0;
  for (std::size_t i = 1; i < p.points.size(); ++i)
    if (dist2(p.points[i], from) < dist2(p.points[best], from)) best = i;
  std::rotate(p.points.begin(), p.points.begin() + static_cast<std::ptrdiff_t>(best), p.points.end());
}

// Orders open paths greedily by nearest end (reversing where that is nearer).
std::vector<ToolPath> order_open(std::vector<ToolPath> paths, Point2& at) {
  std::vector<ToolPath> out;
  out.reserve(paths.size());
  std::vector<char> done(paths.size(), 0);
  for (std::size_t n = 0; n < paths.size(); ++n) {
    std::size_t best = 0;
    bool reverse = false;
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (done[i]) continue;
      const double a = dist2(paths[i].points.front(), at), b = dist2(paths[i].points.back(), at);
      if (a < bd) bd = a, best = i, reverse = false;
      if (!paths[i].closed && b < bd) bd = b, best = i, reverse = true;
    }
    done[best] = 1;
    ToolPath p = std::move(paths[best]);
    if (reverse) std::reverse(p.points.begin(), p.points.end());
    start_nearest(p, at);
    at = p.points.back();
    if (p.closed) at = p.points.front();
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

const char* role_name(PathRole role) {
  switch (role) {
    case PathRole::WallOuter: return "WALL-OUTER";
    case PathRole::WallInner: return "WALL-INNER";
    case PathRole::Skin: return "SKIN";
    default: return "FILL";
  }
}

Region coarse(const Region& region, double tolerance) {
  Region out;
  out.reserve(region.size());
  for (const Ring& r : region) {
    Ring c = simplify(r, tolerance, true);
    if (c.size() >= 3) out.push_back(std::move(c));
  }
  return normalize(out);
}

std::vector<ToolPath> walls(const Region& island, const PrintSettings& s, Region* inner) {
  const double w = s.line_width;
  const double tol = arc_tolerance(s);
  // Where lanes fit and what is left inside are decided on the island simplified to a hundredth
  // of a line (offsets of dense outlines are what costs); the walls printed are exact offsets of
  // the island itself.
  const Region rough = coarse(island, kCoarse * w);
  // The island to within the paths' tolerance: its offsets are within that of the exact ones
  // (an offset moves no point farther than its input moved), with far fewer vertices to offset.
  Region fine;
  for (const Ring& r : island) {
    Ring c = s.path_tolerance > 0 ? simplify(r, s.path_tolerance, true) : r;
    if (c.size() >= 3) fine.push_back(std::move(c));
  }
  std::vector<ToolPath> out;
  Region base = rough;  // the island eroded by (k - 1) widths
  for (int k = 1; k <= s.perimeters && !base.empty(); ++k) {
    const Region core = offset(rough, -k * w, tol);
    const PathRole role = k == 1 ? PathRole::WallOuter : PathRole::WallInner;
    // The wall: the core grown back by half a width, as the exact (k - 1/2) w offset of the
    // island restricted to where the core exists. Where every lane fits, the two are the same
    // region (up to the margin): then the exact offset is the wall as it is.
    const double margin = 1e-4 * w;
    const Region exact_rough = offset(rough, -(k - 0.5) * w, tol);
    const Region grown = dilate_sharp(core, 0.5 * w + margin, s);
    double outline = 0;
    for (const Ring& r : exact_rough) outline += length(r, true);
    const double slack = 0.01 * w * w + outline * margin;
    const Region exact = offset(fine, -(k - 0.5) * w, tol);
    const bool fits = area(exact_rough) - area(grown) <= slack;
    const Region wall = fits ? exact : intersect(exact, grown);
    for (const Ring& r : wall)
      if (r.size() >= 3) out.push_back({role, true, r});
    // What the wall's lane leaves of this band: strips too thin for a lane on each side. Where
    // every lane fits, what is left is no wider than a line anywhere (the band minus its lanes is
    // the band minus its opening by half a width), so nothing to fill. A strip that can take a
    // line is at least a line wide and two long: less area than that is none either.
    if (!fits) {
      const Region lanes = dilate_sharp(core, w + margin, s);
      if (area(base) - area(lanes) > 1.98 * w * w - outline * margin) gap_fill(subtract(base, lanes), s, PathRole::WallInner, out);
    }
    base = core;
  }
  if (inner) *inner = base;
  return out;
}

std::vector<Polyline> line_fill(const Region& region, double spacing, double angle_degrees) {
  FREP_ASSERT(spacing > 0, "line spacing must be positive");
  if (region.empty()) return {};
  const double a = angle_degrees * M_PI / 180, c = std::cos(a), sn = std::sin(a);
  // Coordinates along the lines (v) and across them (u).
  double umin = std::numeric_limits<double>::infinity(), umax = -umin, vmin = umin, vmax = -umin;
  for (const Ring& r : region)
    for (const Point2& p : r) {
      const double u = -sn * p.x + c * p.y, v = c * p.x + sn * p.y;
      umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
    }
  std::vector<Polyline> lines;
  const long long k0 = static_cast<long long>(std::ceil(umin / spacing)), k1 = static_cast<long long>(std::floor(umax / spacing));
  for (long long k = k0; k <= k1; ++k) {
    const double u = static_cast<double>(k) * spacing;
    const double va = vmin - 1, vb = vmax + 1;
    // Alternate directions so that consecutive lines join with short moves.
    Point2 p{c * va - sn * u, sn * va + c * u}, q{c * vb - sn * u, sn * vb + c * u};
    if (k % 2) std::swap(p, q);
    lines.push_back({p, q});
  }
  return clip(lines, region);
}

Region solid_region(const Region& outline, const std::vector<const Region*>& above, const std::vector<const Region*>& below) {
  auto near_surface = [&](const std::vector<const Region*>& layers) -> Region {
    if (layers.empty()) return {};
    Region covered;
    bool first = true;
    for (const Region* r : layers) {
      if (!r || r->empty()) return outline;  // beyond the part: all of this layer is near that surface
      covered = first ? *r : intersect(covered, *r);
      first = false;
      if (covered.empty()) return outline;
    }
    return subtract(outline, covered);
  };
  return unite(near_surface(above), near_surface(below));
}

LayerPlan plan_layer(int index, double z, double section_z, Region outline, const Region& solid,
                     const PrintSettings& s, const InfillSource& gyroid, Point2 start) {
  LayerPlan plan;
  plan.index = index;
  plan.z = z;
  plan.section_z = section_z;
  const double w = s.line_width;
  const double tol = arc_tolerance(s);
  const double skin_angle = index % 2 ? 135 : 45;
  // Slivers of the solid region thinner than half a line (walls that barely lean) are not skin.
  const Region solid_clean = offset(offset(solid, -0.25 * w, tol), 0.25 * w, tol);
  Point2 at = start;
  std::vector<Region> parts = islands(outline);
  // Islands nearest first.
  std::vector<char> done(parts.size(), 0);
  for (std::size_t n = 0; n < parts.size(); ++n) {
    std::size_t best = 0;
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (done[i]) continue;
      for (const Point2& p : parts[i][0])
        if (const double d = dist2(p, at); d < bd) bd = d, best = i;
    }
    done[best] = 1;
    const Region& island = parts[best];
    Region core;
    std::vector<ToolPath> ws = walls(island, s, &core);
    // Inner walls first, the outer wall last (its surface then lies against walls already there).
    std::stable_sort(ws.begin(), ws.end(), [](const ToolPath& a, const ToolPath& b) {
      return (a.role == PathRole::WallOuter) < (b.role == PathRole::WallOuter);
    });
    std::vector<ToolPath> inner_walls, outer_walls;
    for (ToolPath& p : ws) (p.role == PathRole::WallOuter ? outer_walls : inner_walls).push_back(std::move(p));
    for (ToolPath& p : order_open(std::move(inner_walls), at)) plan.paths.push_back(std::move(p));
    for (ToolPath& p : order_open(std::move(outer_walls), at)) plan.paths.push_back(std::move(p));

    // Sparse lines stop where their sides reach `infill_overlap` widths into the walls. Solid
    // lines (skin, full infill) run to the walls' inner edge: the lanes of lines one width
    // apart then fill the inside exactly, on average, whatever the lines' angle to the walls.
    const Region inside = s.perimeters > 0 ? core : offset(island, -0.5 * w, tol);
    if (inside.empty()) continue;
    const Region skin = intersect(inside, solid_clean);
    const Region sparse = subtract(s.perimeters > 0 ? offset(core, -(0.5 - s.infill_overlap) * w, tol) : inside, solid_clean);
    const Region solid_lines = s.infill >= 100 ? subtract(inside, solid_clean) : Region{};
    std::vector<ToolPath> fill;
    for (Polyline& l : line_fill(skin, w, skin_angle)) fill.push_back({PathRole::Skin, false, std::move(l)});
    const double d = s.infill / 100;
    if (d >= 1) {
      for (Polyline& l : line_fill(solid_lines, w, skin_angle)) fill.push_back({PathRole::Fill, false, std::move(l)});
    } else if (d > 0 && !sparse.empty()) {
      std::vector<Polyline> lines;
      if (s.infill_pattern == InfillPattern::Lines) {
        lines = line_fill(sparse, w / d, index % 2 ? 135 : 45);
      } else if (s.infill_pattern == InfillPattern::Grid) {
        lines = line_fill(sparse, 2 * w / d, 45);
        for (Polyline& l : line_fill(sparse, 2 * w / d, 135)) lines.push_back(std::move(l));
      } else {
        FREP_ASSERT(static_cast<bool>(gyroid), "gyroid infill needs its field");
        lines = gyroid(section_z, sparse);
      }
      for (Polyline& l : lines) fill.push_back({PathRole::Fill, false, std::move(l)});
    }
    for (ToolPath& p : order_open(std::move(fill), at)) plan.paths.push_back(std::move(p));
  }
  if (s.path_tolerance > 0)
    for (ToolPath& p : plan.paths) p.points = simplify(p.points, s.path_tolerance, p.closed);
  plan.outline = std::move(outline);
  return plan;
}

}  // namespace frep::slice
