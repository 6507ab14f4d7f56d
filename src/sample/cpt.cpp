// The closest point transform (after Mauch, "A fast algorithm for computing the closest point and
// distance transform", 2000): every feature of the surface -- each face on each side, each edge
// that is not flat, each vertex whose normal cone is not empty -- has a convex "characteristic
// polyhedron" containing every point whose closest surface point lies on that feature. Scanning
// each polyhedron slice by slice and row by row, computing the feature's distance at the grid
// samples inside and keeping the smallest, gives the exact distance everywhere, because the
// polyhedra cover space. The cost is the number of (sample, polyhedron) pairs.
//
// How far a polyhedron must reach: a feature's Voronoi region is a union of segments from the
// feature, so the distances at which it still owns points form an interval [0, T]. Exact
// distances at the centres of coarse cells (4^3 samples, one oracle query each) bound T: a point
// x owned by feature F lies in a cell with centre c and half-diagonal r, and then
// d(c, F) <= d(x, F) + r = d(x) + r <= d(c) + 2r. Walking outward in shells of one cell, the
// first shell without a cell passing that test ends the polyhedron.
//
// Floating point: every half-space is widened by a margin of 1e-12 of the grid's scale, so a
// sample on the boundary between two polyhedra is inside both; the feature's distance just
// outside its own polyhedron differs from the true distance by at most the margin. The winner
// of each sample is then re-evaluated with MeshDistance's own formulas (face plane distance,
// vertex distance, MeshDistance::closest_point_on for edges) and its pseudonormal sign.
#include "sample/cpt.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "frep/math/morton.hpp"
#include "frep/error.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep::sample_detail {
namespace {

constexpr int kCell = 4;                  // samples per edge of a bounding cell
constexpr int kMaxPlanes = 24;            // half-spaces per polyhedron (extra vertex edges are dropped: conservative)
constexpr std::uint32_t kNoOwner = 0xffffffffu;

enum class Kind : std::uint8_t { Face, Edge, Vertex };

struct Feature {
  Kind kind;
  std::int8_t side;        // faces: +1 along the normal (outside), -1 against it
  std::uint32_t element;   // triangle, edge or vertex index
  double reach = 0;        // no sample farther than this from the feature is owned by it
  int lo[3], hi[3];        // index box of the capped polyhedron within the grid (inclusive)
};

struct Half {
  Vec3 n;  // unit
  double d;  // inside: dot(n, p) <= d
};

// One feature's geometry: its polyhedron and what the reach walk needs.
struct Shape {
  Kind kind = Kind::Face;
  Vec3 p[3];          // face corners, edge ends, vertex
  int np = 0;         // base points used
  Vec3 dir;           // face: side * normal; edge: wedge bisector; vertex: cone axis (unit)
  Vec3 anchor;        // centroid, midpoint or vertex
  double base = 0;    // radius of the feature around the anchor
  double spread = 0;  // growth of the cross-section radius per unit of distance
  bool wide = false;  // the cone is too wide to cap along `dir`: bound by the ball around the anchor
  bool cap = true;    // dir . (p - p[0]) <= reach holds on the polyhedron
  Vec3 edir;          // edge: unit direction
  Vec3 normal;        // face: unit normal (signed distances for the scan)
  Half h[kMaxPlanes];
  int nh = 0;
  Vec3 tip[kMaxPlanes];  // the capped polyhedron is the hull of p[] + reach * tip[]
  int ntip = 0;

  // Back to an empty shape of the given kind; the arrays are left as they are (nh, ntip count them).
  void reset(Kind k) {
    kind = k;
    np = nh = ntip = 0;
    dir = anchor = edir = normal = Vec3{};
    base = spread = 0;
    wide = false;
    cap = true;
  }
  void add(const Vec3& n, const Vec3& through) {
    if (nh < kMaxPlanes) h[nh++] = {n, dot(n, through)};
  }
  // A lower bound of the distance from c to the feature.
  double lower(const Vec3& c) const {
    switch (kind) {
      case Kind::Face: return std::max(std::fabs(dot(c - p[0], normal)), length(c - anchor) - base);
      case Kind::Edge: {
        const double t = std::clamp(dot(c - p[0], edir), 0.0, length(p[1] - p[0]));
        return length(c - (p[0] + edir * t));
      }
      case Kind::Vertex: return length(c - p[0]);
    }
    return 0;
  }
  // Squared distance from (x, y, z) to the feature's plane, line or point.
  double dist2(const Vec3& q) const {
    const Vec3 w = q - p[0];
    switch (kind) {
      case Kind::Face: {
        const double t = dot(w, normal);
        return t * t;
      }
      case Kind::Edge: return length2(cross(w, edir));
      case Kind::Vertex: return length2(w);
    }
    return 0;
  }
};

Vec3 unit(const Vec3& v) {
  const double l = length(v);
  return l > 0 ? v / l : Vec3{};
}

struct Context {
  const TriMesh& mesh;
  const MeshTopology& topo;
  const GridSpec& grid;
  std::vector<double> coords[3];  // sample coordinates per axis
  double h[3];                    // spacing per axis
  double margin;                  // widening of every half-space (length)
  int ncell[3];
  std::vector<double> cell_dist;  // exact unsigned distance at each cell centre
  double cell_r;                  // half-diagonal of a cell
  double shell;                   // thickness of a reach shell

  Vec3 cell_center(int a, int b, int c) const {
    const int id[3] = {a, b, c};
    Vec3 v;
    for (int ax = 0; ax < 3; ++ax) v[ax] = grid.bounds.lo[ax] + h[ax] * (kCell * id[ax] + 0.5 * (kCell - 1));
    return v;
  }
  // Position of coordinate x along `axis` in cells: its floor is the cell holding x.
  double cell_position(int axis, double x) const {
    return (x - (grid.bounds.lo[axis] - 0.5 * h[axis])) / (kCell * h[axis]);
  }
  double cell_distance(int a, int b, int c) const {
    return cell_dist[(static_cast<std::size_t>(a) * ncell[1] + b) * ncell[2] + c];
  }
};

// Builds the polyhedron of a feature; false if it has no interior (nothing to scan).
bool make_shape(const Context& ctx, const Feature& f, Shape& s) {
  const TriMesh& m = ctx.mesh;
  s.reset(f.kind);
  switch (f.kind) {
    case Kind::Face: {
      const Vec3& n = ctx.topo.face_normal(f.element);
      if (length2(n) == 0) return false;
      for (int k = 0; k < 3; ++k) s.p[k] = m.corner(f.element, k);
      s.np = 3;
      s.normal = n;
      s.dir = n * static_cast<double>(f.side);
      s.anchor = (s.p[0] + s.p[1] + s.p[2]) / 3.0;
      for (int k = 0; k < 3; ++k) s.base = std::max(s.base, length(s.p[k] - s.anchor));
      for (int k = 0; k < 3; ++k) {
        // Inside the prism: on the triangle's side of each edge's plane along the normal.
        const Vec3 w = unit(cross(n, s.p[(k + 1) % 3] - s.p[k]));
        if (length2(w) == 0) return false;
        s.add(-w, s.p[k]);
      }
      s.add(-s.dir, s.p[0]);  // on this side of the face
      s.tip[s.ntip++] = s.dir;
      return true;
    }
    case Kind::Edge: {
      const auto faces = ctx.topo.edge_faces(f.element);
      if (faces.size() != 2) return false;
      const auto& ev = ctx.topo.edge_vertices(f.element);
      s.p[0] = m.vertices[ev[0]];
      s.p[1] = m.vertices[ev[1]];
      s.np = 2;
      const double len = length(s.p[1] - s.p[0]);
      if (!(len > 0)) return false;
      s.edir = (s.p[1] - s.p[0]) / len;
      s.anchor = (s.p[0] + s.p[1]) * 0.5;
      s.base = len * 0.5;
      Vec3 u[2];
      for (int k = 0; k < 2; ++k) {
        // The direction into face k, perpendicular to the edge: moving that way from the edge
        // gets closer to points on the face's side, so the edge owns only points away from both.
        const Triangle& t = m.triangles[faces[k]];
        std::uint32_t w = t[0];
        for (std::uint32_t v : t)
          if (v != ev[0] && v != ev[1]) w = v;
        const Vec3 a = m.vertices[w] - s.p[0];
        u[k] = unit(a - s.edir * dot(a, s.edir));
      }
      if (length2(u[0] + u[1]) < 1e-24) return false;  // flat: the faces' prisms cover it
      for (int k = 0; k < 2; ++k)
        if (length2(u[k]) > 0) s.add(u[k], s.p[0]);
      s.add(-s.edir, s.p[0]);
      s.add(s.edir, s.p[1]);
      // The wedge's boundary rays and bisector.
      Vec3 r[2];
      for (int k = 0; k < 2; ++k) {
        r[k] = unit(cross(s.edir, u[k]));
        if (dot(u[1 - k], r[k]) > 0) r[k] = -r[k];
      }
      const Vec3 mid = r[0] + r[1];
      const double cmin = length2(mid) > 1e-12 ? std::min(dot(unit(mid), r[0]), dot(unit(mid), r[1])) : 0;
      if (length2(u[0]) == 0 || length2(u[1]) == 0 || cmin < 0.05) {
        s.wide = true;
        s.cap = false;
        s.spread = 3.2;
        return true;
      }
      s.dir = unit(mid);
      s.spread = 0.5 * std::acos(std::clamp(dot(r[0], r[1]), -1.0, 1.0));
      for (int k = 0; k < 2; ++k) s.tip[s.ntip++] = r[k] / dot(s.dir, r[k]);
      return true;
    }
    case Kind::Vertex: {
      const auto faces = ctx.topo.vertex_faces(f.element);
      if (faces.empty()) return false;
      s.p[0] = m.vertices[f.element];
      s.np = 1;
      s.anchor = s.p[0];
      // Neighbours: moving from the vertex along any of its edges must not get closer.
      std::uint32_t nb[64];
      int count = 0;
      for (std::uint32_t t : faces)
        for (std::uint32_t v : m.triangles[t])
          if (v != f.element && count < 64 && std::find(nb, nb + count, v) == nb + count) nb[count++] = v;
      Vec3 e[64];
      int ne = 0;
      for (int k = 0; k < count; ++k) {
        const Vec3 d = unit(m.vertices[nb[k]] - s.p[0]);
        if (length2(d) > 0) e[ne++] = d;
      }
      for (int k = 0; k < ne; ++k) s.add(e[k], s.p[0]);
      // Extreme rays of the cone {x : x . e_k <= 0 for all k}: along cross products of pairs.
      Vec3 gen[kMaxPlanes];
      int ng = 0;
      bool overflow = false;
      for (int a = 0; a < ne; ++a)
        for (int b = a + 1; b < ne; ++b) {
          const Vec3 c = unit(cross(e[a], e[b]));
          if (length2(c) == 0) continue;
          for (double sg : {1.0, -1.0}) {
            const Vec3 g = c * sg;
            bool ok = true;
            for (int k = 0; k < ne && ok; ++k) ok = dot(g, e[k]) <= 1e-9;
            if (!ok) continue;
            bool dup = false;
            for (int k = 0; k < ng && !dup; ++k) dup = dot(gen[k], g) > 1 - 1e-12;
            if (dup) continue;
            if (ng < kMaxPlanes) gen[ng++] = g;
            else overflow = true;
          }
        }
      if (ng == 0) return false;  // the cone is the vertex alone (a saddle)
      bool line = true;           // all rays on one line: no interior (a flat vertex)
      for (int k = 1; k < ng && line; ++k) line = std::fabs(dot(gen[k], gen[0])) > 1 - 1e-9;
      if (line) return false;
      Vec3 sum;
      for (int k = 0; k < ng; ++k) sum += gen[k];
      double cmin = -1;
      if (length2(sum) > 1e-12 && !overflow) {
        s.dir = unit(sum);
        cmin = 1;
        for (int k = 0; k < ng; ++k) cmin = std::min(cmin, dot(s.dir, gen[k]));
      }
      if (cmin < 0.05) {
        s.wide = true;
        s.cap = false;
        s.spread = 3.2;
        return true;
      }
      s.spread = std::acos(std::clamp(cmin, -1.0, 1.0));
      for (int k = 0; k < ng && s.ntip < kMaxPlanes; ++k) s.tip[s.ntip++] = gen[k] / dot(s.dir, gen[k]);
      return true;
    }
  }
  return false;
}

// Bounding box of the polyhedron capped at distance `reach`.
Box3 shape_box(const Shape& s, double reach) {
  Box3 b;
  for (int k = 0; k < s.np; ++k) {
    if (s.wide) {
      b.add(s.p[k] - Vec3{reach, reach, reach});
      b.add(s.p[k] + Vec3{reach, reach, reach});
      continue;
    }
    b.add(s.p[k]);
    for (int t = 0; t < s.ntip; ++t) b.add(s.p[k] + s.tip[t] * reach);
  }
  return b;
}

// How far the feature can own samples (0: nowhere), by the shell walk described above.
double find_reach(const Context& ctx, const Shape& s) {
  const Box3& gb = ctx.grid.bounds;
  const double tol = ctx.margin * 4;
  double reach = 0;
  int hint[3] = {-1, -1, -1};
  for (int shell = 0;; ++shell) {
    const double t0 = shell * ctx.shell, t1 = t0 + ctx.shell, tm = 0.5 * (t0 + t1);
    Vec3 center = s.anchor;
    double rho = s.base + t1;  // every point within t1 of the feature
    if (!s.wide) {
      const double r2 = s.base + 0.5 * ctx.shell + t1 * s.spread;
      if (r2 < rho) center = s.anchor + s.dir * tm, rho = r2;
    }
    int lo[3], hi[3];
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(0, static_cast<int>(std::floor(ctx.cell_position(a, center[a] - rho))));
      hi[a] = std::min(ctx.ncell[a] - 1, static_cast<int>(std::floor(ctx.cell_position(a, center[a] + rho))));
      if (!(center[a] + rho >= gb.lo[a] - ctx.h[a]) || !(center[a] - rho <= gb.hi[a] + ctx.h[a]) || lo[a] > hi[a])
        empty = true;
    }
    if (empty) break;
    // An owned point at distance t from the feature lies in its polyhedron, so its height above
    // the feature along the axis is between t cos(spread) and t: the shell is a slab along `dir`.
    const double ball = rho + ctx.cell_r + tol;
    const double slab_lo = t0 * std::cos(s.spread) - ctx.cell_r - tol, slab_hi = t1 + ctx.cell_r + tol;
    const auto passes = [&](int a, int b, int c) {
      const Vec3 cc = ctx.cell_center(a, b, c);
      if (length(cc - center) > ball) return false;
      if (!s.wide) {
        const double u = dot(cc - s.anchor, s.dir);
        if (u < slab_lo || u > slab_hi) return false;
      }
      // Points at distance >= t0 from the feature are at least t0 - base from its anchor.
      if (length(cc - s.anchor) < t0 - s.base - ctx.cell_r - tol) return false;
      return s.lower(cc) <= ctx.cell_distance(a, b, c) + 2 * ctx.cell_r + tol;
    };
    // The cell on the axis at the shell's middle, or the last shell's passing cell, usually passes:
    // trying them first saves scanning the whole box.
    bool relevant = false;
    {
      int cell[3];
      for (int a = 0; a < 3; ++a)
        cell[a] = std::clamp(static_cast<int>(std::floor(ctx.cell_position(a, center[a]))), lo[a], hi[a]);
      relevant = passes(cell[0], cell[1], cell[2]);
      if (!relevant && hint[0] >= 0) {
        for (int a = 0; a < 3; ++a) cell[a] = std::clamp(hint[a], lo[a], hi[a]);
        relevant = passes(cell[0], cell[1], cell[2]);
      }
    }
    // The whole box otherwise, each row of cells cut to the ball and the slab first (the cuts are
    // widened by a cell; `passes` decides).
    for (int a = lo[0]; a <= hi[0] && !relevant; ++a)
      for (int b = lo[1]; b <= hi[1] && !relevant; ++b) {
        const Vec3 row = ctx.cell_center(a, b, 0);
        const double dx = row.x - center.x, dy = row.y - center.y, r2 = ball * ball - dx * dx - dy * dy;
        if (r2 < 0) continue;
        double zl = center.z - std::sqrt(r2), zu = center.z + std::sqrt(r2);
        if (!s.wide && std::fabs(s.dir.z) > 1e-6) {
          const double w = (row.x - s.anchor.x) * s.dir.x + (row.y - s.anchor.y) * s.dir.y;
          double z0 = s.anchor.z + (slab_lo - w) / s.dir.z, z1 = s.anchor.z + (slab_hi - w) / s.dir.z;
          if (z0 > z1) std::swap(z0, z1);
          zl = std::max(zl, z0), zu = std::min(zu, z1);
        }
        if (!(zl <= zu)) continue;
        const int c0 = std::max(lo[2], static_cast<int>(std::floor(ctx.cell_position(2, zl))) - 1);
        const int c1 = std::min(hi[2], static_cast<int>(std::ceil(ctx.cell_position(2, zu))) + 1);
        for (int c = c0; c <= c1 && !relevant; ++c)
          if (passes(a, b, c)) relevant = true, hint[0] = a, hint[1] = b, hint[2] = c;
      }
    if (!relevant) break;
    reach = t1;
  }
  return reach;
}

// The capped polyhedron's sample-index box within the grid; false if it misses the grid.
bool index_box(const Context& ctx, const Shape& s, double reach, int lo[3], int hi[3]) {
  const Box3 b = shape_box(s, reach);
  for (int a = 0; a < 3; ++a) {
    const int n = ctx.grid.counts[a];
    const double o = ctx.grid.bounds.lo[a];
    const double l = std::floor((b.lo[a] - o) / ctx.h[a]) - 1, u = std::ceil((b.hi[a] - o) / ctx.h[a]) + 1;
    lo[a] = static_cast<int>(std::clamp(l, 0.0, static_cast<double>(n)));
    hi[a] = static_cast<int>(std::clamp(u, -1.0, static_cast<double>(n - 1)));
    if (lo[a] > hi[a]) return false;
  }
  return true;
}

// Corners of the polyhedron capped at `reach` (its convex hull).
int shape_points(const Shape& s, double reach, Vec3* out) {
  int n = 0;
  if (s.wide) {
    const Box3 b = shape_box(s, reach);
    for (int k = 0; k < 8; ++k) out[n++] = {(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z};
    return n;
  }
  for (int k = 0; k < s.np; ++k) {
    out[n++] = s.p[k];
    for (int t = 0; t < s.ntip; ++t) out[n++] = s.p[k] + s.tip[t] * reach;
  }
  return n;
}

struct P2 {
  double x, y;
};

// Convex hull of points in the plane, counter-clockwise (Andrew's monotone chain); returns its size.
int hull2(P2* p, int n, P2* h) {
  std::sort(p, p + n, [](const P2& a, const P2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  auto cross2 = [](const P2& o, const P2& a, const P2& b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (int i = n - 2, t = k + 1; i >= 0; --i) {
    while (k >= t && cross2(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  return n > 1 ? k - 1 : n;
}

// Scans one feature's polyhedron over the slices [i0, i1) (within its index box): the slices
// and rows that meet the polyhedron come from its shadow on the (x, y) plane (the hull of its
// corners' shadows); the run of samples along each z row, from the half-spaces.
std::uint64_t scan(const Context& ctx, const Shape& s, double reach, std::uint32_t id, const int lo[3],
                   const int hi[3], int i0, int i1, double* best, std::uint32_t* owner) {
  const GridSpec& g = ctx.grid;
  const std::vector<double>& X = ctx.coords[0];
  const std::vector<double>& Y = ctx.coords[1];
  const std::vector<double>& Z = ctx.coords[2];
  const double x0 = X[0], y0 = Y[0], z0 = Z[0], hx = ctx.h[0], hy = ctx.h[1], hz = ctx.h[2];
  Vec3 pts[2 * kMaxPlanes + 8];
  const int np = shape_points(s, reach, pts);
  P2 sh[2 * kMaxPlanes + 8], hull[2 * kMaxPlanes + 10];
  for (int k = 0; k < np; ++k) sh[k] = {pts[k].x, pts[k].y};
  const int nhull = hull2(sh, np, hull);
  double xmin = INFINITY, xmax = -INFINITY;
  for (int k = 0; k < nhull; ++k) xmin = std::min(xmin, hull[k].x), xmax = std::max(xmax, hull[k].x);
  // Rows within a hair of the shadow are scanned too: the half-spaces (with their margin) decide.
  const double pad = 1e-6;
  const int ia = std::max({i0, lo[0], static_cast<int>(std::ceil((xmin - x0) / hx - pad))});
  const int ib = std::min({i1 - 1, hi[0], static_cast<int>(std::floor((xmax - x0) / hx + pad))});
  // Per half-space: 1 / n.z and the constant part of the row bound.
  double inv[kMaxPlanes], rx[kMaxPlanes];
  std::uint64_t evals = 0;
  for (int i = ia; i <= ib; ++i) {
    const double x = X[static_cast<std::size_t>(i)];
    // The shadow's extent in y at this x (edges meeting the vertical line, within the pad).
    const double xl = x - pad * hx, xu = x + pad * hx;
    double ymin = INFINITY, ymax = -INFINITY;
    for (int k = 0; k < nhull; ++k) {
      const P2 a = hull[k], b = hull[(k + 1) % std::max(nhull, 1)];
      const double ex0 = std::min(a.x, b.x), ex1 = std::max(a.x, b.x);
      if (ex1 < xl || ex0 > xu) continue;
      if (ex1 - ex0 <= 2 * pad * hx) {
        ymin = std::min({ymin, a.y, b.y}), ymax = std::max({ymax, a.y, b.y});
        continue;
      }
      const double t = std::clamp((x - a.x) / (b.x - a.x), 0.0, 1.0);
      const double y = a.y + (b.y - a.y) * t;
      ymin = std::min(ymin, y), ymax = std::max(ymax, y);
    }
    if (!(ymin <= ymax)) continue;
    const int ja = std::max(lo[1], static_cast<int>(std::ceil((ymin - y0) / hy - pad)));
    const int jb = std::min(hi[1], static_cast<int>(std::floor((ymax - y0) / hy + pad)));
    if (ja > jb) continue;
    for (int k = 0; k < s.nh; ++k) {
      rx[k] = s.h[k].d - s.h[k].n.x * x + ctx.margin;
      inv[k] = s.h[k].n.z != 0 ? 1 / s.h[k].n.z : 0;
    }
    for (int j = ja; j <= jb; ++j) {
      const double y = Y[static_cast<std::size_t>(j)];
      double zl = -INFINITY, zu = INFINITY;
      for (int k = 0; k < s.nh; ++k) {
        const double r = rx[k] - s.h[k].n.y * y;
        const double nz = s.h[k].n.z;
        if (nz > 0) zu = std::min(zu, r * inv[k]);
        else if (nz < 0) zl = std::max(zl, r * inv[k]);
        else if (r < 0) zu = -INFINITY;
      }
      if (!(zl <= zu)) continue;
      // Division by n.z replaced by a multiplication: widen by a relative hair to stay conservative.
      const double wz = 1e-9 + 1e-12 * (std::fabs(zl) + std::fabs(zu)) / hz;
      const int k0 = std::max(lo[2], static_cast<int>(std::clamp(std::ceil((zl - z0) / hz - wz), -1.0, 1e9)));
      const int k1 = std::min(hi[2], static_cast<int>(std::clamp(std::floor((zu - z0) / hz + wz), -1.0, 1e9)));
      if (k0 > k1) continue;
      evals += static_cast<std::uint64_t>(k1 - k0 + 1);
      const std::size_t row = g.index(i, j, 0);
      double* bd = best + row;
      std::uint32_t* ow = owner + row;
      // The feature's squared distance along the row: w = (x, y, z) - p0.
      const double wx = x - s.p[0].x, wy = y - s.p[0].y;
      switch (s.kind) {
        case Kind::Face: {
          const double base = s.normal.x * wx + s.normal.y * wy;
          for (int k = k0; k <= k1; ++k) {
            const double t = base + s.normal.z * (Z[static_cast<std::size_t>(k)] - s.p[0].z);
            const double d2 = t * t;
            if (d2 < bd[k] || (d2 == bd[k] && id < ow[k])) bd[k] = d2, ow[k] = id;
          }
          break;
        }
        case Kind::Edge: {
          // |w x e|^2 with w = (wx, wy, wz): the cross product is linear in wz.
          const Vec3 e = s.edir;
          const double cx0 = wy * e.z, cy0 = -wx * e.z, cz = wx * e.y - wy * e.x;
          for (int k = k0; k <= k1; ++k) {
            const double wz = Z[static_cast<std::size_t>(k)] - s.p[0].z;
            const double cx = cx0 - wz * e.y, cy = cy0 + wz * e.x;
            const double d2 = cx * cx + cy * cy + cz * cz;
            if (d2 < bd[k] || (d2 == bd[k] && id < ow[k])) bd[k] = d2, ow[k] = id;
          }
          break;
        }
        case Kind::Vertex: {
          const double r2 = wx * wx + wy * wy;
          for (int k = k0; k <= k1; ++k) {
            const double wz = Z[static_cast<std::size_t>(k)] - s.p[0].z;
            const double d2 = r2 + wz * wz;
            if (d2 < bd[k] || (d2 == bd[k] && id < ow[k])) bd[k] = d2, ow[k] = id;
          }
          break;
        }
      }
    }
  }
  return evals;
}

}  // namespace

template <class T>
void closest_point_transform(const MeshField& field, const GridSpec& grid, ThreadPool& pool, T* out,
                             const MeshGridOptions& options, MeshGridStats& stats) {
  FREP_ASSERT(field.solid() && field.sign() == SignMethod::Pseudonormal, "CPT needs a solid with pseudonormal signs");
  const auto tstart = std::chrono::steady_clock::now();
  const bool debug = std::getenv("FREP_CPT_DEBUG") != nullptr;
  const auto report = [&](const char* stage, double f) {
    if (debug) std::fprintf(stderr, "cpt %-16s %.3f s\n", stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - tstart).count());
    if (options.progress) options.progress(stage, f);
  };
  const TriMesh& mesh = field.welded();
  const MeshTopology& topo = field.topology();
  const MeshDistance& md = field.distance();
  Context ctx{mesh, topo, grid, {}, {}, 0, {}, {}, 0, 0};
  double scale = 0;
  for (int a = 0; a < 3; ++a) {
    const int n = grid.counts[a];
    ctx.coords[a].resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) ctx.coords[a][static_cast<std::size_t>(i)] = grid.coord(a, i);
    ctx.h[a] = (grid.bounds.hi[a] - grid.bounds.lo[a]) / (n - 1);
    ctx.ncell[a] = (n + kCell - 1) / kCell;
    scale = std::max({scale, std::fabs(grid.bounds.lo[a]), std::fabs(grid.bounds.hi[a]),
                      grid.bounds.hi[a] - grid.bounds.lo[a]});
  }
  ctx.margin = 1e-12 * scale;
  ctx.cell_r = 0.5 * kCell * std::sqrt(ctx.h[0] * ctx.h[0] + ctx.h[1] * ctx.h[1] + ctx.h[2] * ctx.h[2]);
  ctx.shell = kCell * std::min({ctx.h[0], ctx.h[1], ctx.h[2]});

  // 1. Exact distances at the cell centres.
  report("distance bounds", 0);
  const std::size_t cells = static_cast<std::size_t>(ctx.ncell[0]) * ctx.ncell[1] * ctx.ncell[2];
  ctx.cell_dist.resize(cells);
  pool.parallel_for_ranges(cells, 256, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      const int k = static_cast<int>(c % ctx.ncell[2]), j = static_cast<int>((c / ctx.ncell[2]) % ctx.ncell[1]),
                i = static_cast<int>(c / (static_cast<std::size_t>(ctx.ncell[2]) * ctx.ncell[1]));
      ctx.cell_dist[c] = md.unsigned_distance(ctx.cell_center(i, j, k));
    }
  });

  // 2. Features and how far each reaches.
  report("polyhedra", 0.1);
  std::vector<Feature> features;
  features.reserve(2 * mesh.triangles.size() + topo.num_edges() + topo.num_vertices());
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    if (topo.usable(t)) {
      features.push_back({Kind::Face, 1, t, 0, {}, {}});
      features.push_back({Kind::Face, -1, t, 0, {}, {}});
    }
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) features.push_back({Kind::Edge, 0, e, 0, {}, {}});
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v)
    if (!topo.vertex_faces(v).empty()) features.push_back({Kind::Vertex, 0, v, 0, {}, {}});
  FREP_ASSERT(features.size() < kNoOwner, "too many features");
  {
    // Spatial order (Morton code of a point of the feature): consecutive features then touch
    // neighbouring rows of the scratch grids, which keeps the scan in cache.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> key(features.size());
    const Box3& gb = grid.bounds;
    for (std::size_t i = 0; i < features.size(); ++i) {
      const Feature& f = features[i];
      const Vec3 p = f.kind == Kind::Face ? mesh.corner(f.element, 0)
                     : f.kind == Kind::Edge ? mesh.vertices[topo.edge_vertices(f.element)[0]]
                                            : mesh.vertices[f.element];
      std::uint64_t code = 0;
      for (int a = 0; a < 3; ++a) {
        const double u = std::clamp((p[a] - gb.lo[a]) / (gb.hi[a] - gb.lo[a]), 0.0, 1.0);
        code |= morton_spread(static_cast<std::uint64_t>(u * kMortonCells)) << (2 - a);
      }
      key[i] = {code, static_cast<std::uint32_t>(i)};
    }
    std::sort(key.begin(), key.end());
    std::vector<Feature> sorted(features.size());
    for (std::size_t i = 0; i < key.size(); ++i) sorted[i] = features[key[i].second];
    features.swap(sorted);
  }
  pool.parallel_for_ranges(features.size(), 512, [&](int, std::size_t b, std::size_t e) {
    Shape s;
    for (std::size_t i = b; i < e; ++i) {
      Feature& f = features[i];
      f.reach = 0;
      if (!make_shape(ctx, f, s)) continue;
      f.reach = find_reach(ctx, s);
      if (f.reach > 0 && !index_box(ctx, s, f.reach, f.lo, f.hi)) f.reach = 0;
    }
  });

  if (debug) {
    double sum[3] = {0, 0, 0}; std::size_t cnt[3] = {0, 0, 0}, wide[3] = {0, 0, 0}, zero[3] = {0, 0, 0};
    Shape sh;
    for (const Feature& f : features) {
      const int k = static_cast<int>(f.kind);
      if (f.reach <= 0) { ++zero[k]; continue; }
      make_shape(ctx, f, sh);
      ++cnt[k]; sum[k] += f.reach / ctx.shell; wide[k] += sh.wide;
    }
    for (int k = 0; k < 3; ++k) std::fprintf(stderr, "kind %d: %zu used, %zu unused, %zu wide, mean reach %.2f shells\n", k, cnt[k], zero[k], wide[k], cnt[k] ? sum[k] / cnt[k] : 0.0);
  }
  // 3. Scan, slab by slab of slices: each slab is one worker's, so no two workers write the same
  // sample, and ties go to the lower feature index, so the result does not depend on the order.
  report("scan", 0.25);
  const std::size_t n = grid.size();
  std::vector<double> best(n, INFINITY);
  std::vector<std::uint32_t> owner(n, kNoOwner);
  const int nx = grid.counts[0];
  const int slabs = std::min(nx, 8 * pool.size());
  auto slab_begin = [&](int s) { return static_cast<int>(static_cast<long long>(nx) * s / slabs); };
  std::vector<std::vector<std::uint32_t>> buckets(static_cast<std::size_t>(slabs));
  std::size_t used = 0;
  for (std::uint32_t i = 0; i < features.size(); ++i) {
    const Feature& f = features[i];
    if (f.reach <= 0) continue;
    ++used;
    for (int s = 0; s < slabs; ++s)
      if (f.lo[0] < slab_begin(s + 1) && f.hi[0] >= slab_begin(s)) buckets[static_cast<std::size_t>(s)].push_back(i);
  }
  std::atomic<std::uint64_t> evaluations{0};
  std::atomic<int> slabs_done{0};
  pool.parallel_for(slabs, [&](int, int s) {
    Shape sh;
    std::uint64_t ev = 0;
    for (std::uint32_t id : buckets[static_cast<std::size_t>(s)]) {
      const Feature& f = features[id];
      if (!make_shape(ctx, f, sh)) continue;
      if (sh.cap) sh.add(sh.dir, sh.p[0] + sh.dir * f.reach);
      ev += scan(ctx, sh, f.reach, id, f.lo, f.hi, slab_begin(s), slab_begin(s + 1), best.data(), owner.data());
    }
    evaluations += ev;
    report("scan", 0.25 + 0.6 * (++slabs_done) / slabs);
  });

  // 4. Each sample's value from the feature that won it, with MeshDistance's formulas and signs.
  report("signs", 0.85);
  std::atomic<std::size_t> fallback{0};
  const int ny = grid.counts[1], nz = grid.counts[2];
  pool.parallel_for(nx, [&](int, int i) {
    std::size_t fb = 0;
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const std::size_t idx = grid.index(i, j, k);
        const Vec3 p{ctx.coords[0][static_cast<std::size_t>(i)], ctx.coords[1][static_cast<std::size_t>(j)],
                     ctx.coords[2][static_cast<std::size_t>(k)]};
        const std::uint32_t o = owner[idx];
        double v;
        if (o == kNoOwner) {
          ++fb;
          v = field.signed_distance(p);
        } else {
          const Feature& f = features[o];
          switch (f.kind) {
            case Kind::Face: {
              v = dot(p - mesh.corner(f.element, 0), topo.face_normal(f.element));
              if (v == 0) v = 0;  // no negative zero
              break;
            }
            case Kind::Vertex: {
              const Vec3 w = p - mesh.vertices[f.element];
              const double d = length(w);
              const double sd = dot(w, topo.vertex_pseudonormal(f.element));
              v = d == 0 ? 0 : (sd > 0 ? d : (sd < 0 ? -d : field.signed_distance(p)));
              break;
            }
            case Kind::Edge: {
              const ClosestPoint c = md.closest_point_on(p, topo.edge_faces(f.element)[0]);
              const int sg = c.distance == 0 ? 1 : md.pseudonormal_sign(p, c);
              v = c.distance == 0 ? 0 : (sg != 0 ? sg * c.distance : field.signed_distance(p));
              break;
            }
            default: v = field.signed_distance(p);
          }
        }
        out[idx] = static_cast<T>(v);
      }
    fallback += fb;
  });
  stats.features = used;
  stats.evaluations = evaluations;
  stats.fallback_samples = fallback;
  report("done", 1);
}

template void closest_point_transform<float>(const MeshField&, const GridSpec&, ThreadPool&, float*,
                                             const MeshGridOptions&, MeshGridStats&);
template void closest_point_transform<double>(const MeshField&, const GridSpec&, ThreadPool&, double*,
                                              const MeshGridOptions&, MeshGridStats&);

}  // namespace frep::sample_detail
