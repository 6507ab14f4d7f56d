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
//
// Truncated grids (values clamped to +-D): a sample at distance d <= D lies in its owner's
// polyhedron at a height of at most d along the axis, and so does every feature whose distance
// there could win it, so capping every reach at the band (D, widened by a hair) keeps the winner,
// hence the value, of every sample within D bit for bit; the walk and its oracle queries are
// skipped for narrow bands. A sample whose winner is farther than the band (or that no capped
// polyhedron reached) is farther than D from the surface: it only needs its side. Two
// neighbouring samples on opposite sides are both within a voxel edge of the surface (the segment
// between them crosses it), so with a band at least a voxel edge wide, no sample beyond the band
// neighbours a band sample or a beyond-the-band sample on the other side: each connected region
// of samples beyond the band takes the side of the band samples around it (a flood fill, row by
// row), and a grid without a band sample is one region, whose side one oracle query tells. The
// sides are the true ones, so the result does not depend on the order of the fill.
#include "sample/cpt.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "frep/error.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/util/thread_pool.hpp"
#include "util/morton.hpp"

namespace frep::sample_detail {
namespace {

constexpr int kCell = 4;                  // samples per edge of a bounding cell
constexpr int kMaxPlanes = 24;            // half-spaces per polyhedron (extra vertex edges are dropped: conservative)
constexpr std::uint32_t kNoOwner = 0xffffffffu;

enum class Kind : std::uint8_t { Face, Edge, Vertex };

struct Feature {
  Kind kind;
  std::int8_t side;        // faces: +1 along the normal (outside), -1 against it, 0 both (truncated grids)
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
  bool both = false;  // face: both sides, so also -dir . (p - p[0]) <= reach
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
    both = false;
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
      s.dir = f.side < 0 ? -n : n;
      s.anchor = (s.p[0] + s.p[1] + s.p[2]) / 3.0;
      for (int k = 0; k < 3; ++k) s.base = std::max(s.base, length(s.p[k] - s.anchor));
      for (int k = 0; k < 3; ++k) {
        // Inside the prism: on the triangle's side of each edge's plane along the normal.
        const Vec3 w = unit(cross(n, s.p[(k + 1) % 3] - s.p[k]));
        if (length2(w) == 0) return false;
        s.add(-w, s.p[k]);
      }
      s.tip[s.ntip++] = s.dir;
      if (f.side) {
        s.add(-s.dir, s.p[0]);  // on this side of the face
      } else {
        // Both sides at once (truncated grids: one prism through the face instead of two, each
        // set up on its own; the value is the plane's signed distance either way).
        s.both = true;
        s.tip[s.ntip++] = -s.dir;
      }
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

// How far the feature can own samples (0: nowhere), by the shell walk described above; the walk
// stops once it reaches `limit` (the band of a truncated grid).
double find_reach(const Context& ctx, const Shape& s, double limit) {
  const Box3& gb = ctx.grid.bounds;
  const double tol = ctx.margin * 4;
  double reach = 0;
  int hint[3] = {-1, -1, -1};
  for (int shell = 0; reach < limit; ++shell) {
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

// The sample-index box of `b` within the grid, a sample wider on each side; false if it misses
// the grid.
bool index_box(const Context& ctx, const Box3& b, int lo[3], int hi[3]) {
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

// The box of the points within `r` of a feature (for a truncated grid, the only points whose
// value a feature can decide), without building its polyhedron.
Box3 near_box(const Context& ctx, const Feature& f, double r) {
  Box3 b;
  switch (f.kind) {
    case Kind::Face:
      for (int k = 0; k < 3; ++k) b.add(ctx.mesh.corner(f.element, k));
      break;
    case Kind::Edge:
      for (std::uint32_t v : ctx.topo.edge_vertices(f.element)) b.add(ctx.mesh.vertices[v]);
      break;
    case Kind::Vertex: b.add(ctx.mesh.vertices[f.element]); break;
  }
  return b.inflated(r);
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

// The scan's scratch: per sample, the smallest squared distance yet and its feature, found row
// (i, j) by row. Full grids hold every row, in one array; truncated ones give a row its storage
// when a polyhedron first reaches it, from blocks of the slab that owns the row (so that workers
// never share a block): memory and its clearing go to the rows near the surface only.
class RowScratch {
 public:
  RowScratch(int nx, int ny, int nz, int slabs)
      : ny_(ny), nz_(nz), best_(static_cast<std::size_t>(nx) * ny, nullptr), owner_(best_.size(), nullptr),
        arenas_(static_cast<std::size_t>(slabs)) {}
  // Every row, cleared in parallel (hundreds of megabytes are a stage of their own on one core).
  void allocate_all(ThreadPool& pool) {
    const std::size_t rows = best_.size(), n = rows * static_cast<std::size_t>(nz_);
    dense_best_.reset(new double[n]);
    dense_owner_.reset(new std::uint32_t[n]);
    for (std::size_t r = 0; r < rows; ++r)
      best_[r] = dense_best_.get() + r * nz_, owner_[r] = dense_owner_.get() + r * nz_;
    pool.parallel_for_ranges(rows, static_cast<std::size_t>(ny_), [&](int, std::size_t b, std::size_t e) {
      std::fill(dense_best_.get() + b * nz_, dense_best_.get() + e * nz_, INFINITY);
      std::fill(dense_owner_.get() + b * nz_, dense_owner_.get() + e * nz_, kNoOwner);
    });
  }
  // Row (i, j)'s storage, made by the worker that owns slab `slab` if it has none yet.
  void row(int i, int j, int slab, double*& best, std::uint32_t*& owner) {
    const std::size_t r = static_cast<std::size_t>(i) * ny_ + j;
    if (!best_[r]) {
      Arena& a = arenas_[static_cast<std::size_t>(slab)];
      if (a.used == kBlockRows) a.used = 0;
      if (a.used == 0) {
        a.best.emplace_back(new double[kBlockRows * nz_]);
        a.owner.emplace_back(new std::uint32_t[kBlockRows * nz_]);
      }
      best_[r] = a.best.back().get() + a.used * nz_;
      owner_[r] = a.owner.back().get() + a.used * nz_;
      ++a.used;
      std::fill_n(best_[r], nz_, INFINITY);
      std::fill_n(owner_[r], nz_, kNoOwner);
    }
    best = best_[r], owner = owner_[r];
  }
  // Row (i, j)'s storage, or nulls if no polyhedron reached it.
  const double* best(int i, int j) const { return best_[static_cast<std::size_t>(i) * ny_ + j]; }
  const std::uint32_t* owner(int i, int j) const { return owner_[static_cast<std::size_t>(i) * ny_ + j]; }

 private:
  static constexpr std::size_t kBlockRows = 64;
  struct Arena {
    std::vector<std::unique_ptr<double[]>> best;
    std::vector<std::unique_ptr<std::uint32_t[]>> owner;
    std::size_t used = 0;  // rows used in the last block
  };
  int ny_, nz_;
  std::vector<double*> best_;
  std::vector<std::uint32_t*> owner_;
  std::unique_ptr<double[]> dense_best_;
  std::unique_ptr<std::uint32_t[]> dense_owner_;
  std::vector<Arena> arenas_;
};

// Scans one feature's polyhedron over the slices [i0, i1) (within its index box): the slices
// and rows that meet the polyhedron come from its shadow on the (x, y) plane (the hull of its
// corners' shadows); the run of samples along each z row, from the half-spaces.
std::uint64_t scan(const Context& ctx, const Shape& s, double reach, std::uint32_t id, const int lo[3],
                   const int hi[3], int i0, int i1, RowScratch& rows, int slab) {
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
      double* bd;
      std::uint32_t* ow;
      rows.row(i, j, slab, bd, ow);
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

// The largest voxel edge of the grid.
double max_spacing(const GridSpec& grid) {
  double h = 0;
  for (int a = 0; a < 3; ++a) h = std::max(h, (grid.bounds.hi[a] - grid.bounds.lo[a]) / (grid.counts[a] - 1));
  return h;
}

}  // namespace

double truncation_band(const GridSpec& grid, double truncate) {
  // The hair (a millionth) is far above the rounding of the distances (1e-12 of the grid's scale,
  // and the band is at least a voxel, 1/4095 of it) and far below anything a user would see.
  return std::max(truncate, max_spacing(grid)) * (1 + 1e-6);
}

bool truncation_scans_band(const GridSpec& grid, double truncate) {
  return truncate > 0 && truncation_band(grid, truncate) <= kScanBandVoxels * max_spacing(grid);
}

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
  // Truncation: values within `band` are exact, every reach is capped at `cap` (the band and what
  // the rounding of the margins needs), and the walk runs only for wide bands.
  const double trunc = options.truncate;
  const bool truncated = trunc > 0;
  const double band = truncated ? truncation_band(grid, trunc) : INFINITY;
  const double cap = truncated ? band * (1 + 1e-6) + 16 * ctx.margin : INFINITY;
  const bool walk = !truncation_scans_band(grid, trunc);

  // 1. Exact distances at the cell centres (for the walk).
  if (walk) {
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
  }

  // 2. Features and how far each reaches.
  report("polyhedra", 0.1);
  std::vector<Feature> features;
  features.reserve(2 * mesh.triangles.size() + topo.num_edges() + topo.num_vertices());
  // Without the walk, a face's two sides are one feature, in the place of its outer side:
  // features keep their order, so ties between features (the lower index wins) go the same way
  // as in a full grid, and a face's value does not depend on its side.
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    if (topo.usable(t)) {
      if (walk) {
        features.push_back({Kind::Face, 1, t, 0, {}, {}});
        features.push_back({Kind::Face, -1, t, 0, {}, {}});
      } else {
        features.push_back({Kind::Face, 0, t, 0, {}, {}});
      }
    }
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) features.push_back({Kind::Edge, 0, e, 0, {}, {}});
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v)
    if (!topo.vertex_faces(v).empty()) features.push_back({Kind::Vertex, 0, v, 0, {}, {}});
  FREP_ASSERT(features.size() < kNoOwner, "too many features");
  {
    // Spatial order (Morton code of a point of the feature): consecutive features then touch
    // neighbouring rows of the scratch grids, which keeps the scan in cache.
    // Keys are unique (the index breaks ties), so sorting runs in parallel and merging them gives
    // the one sorted order.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> key(features.size());
    const Box3& gb = grid.bounds;
    const std::size_t parts = static_cast<std::size_t>(pool.size());
    const auto part = [&](std::size_t k) { return key.begin() + static_cast<std::ptrdiff_t>(key.size() * k / parts); };
    pool.parallel_for(static_cast<int>(parts), [&](int, int k) {
      const std::size_t b = key.size() * static_cast<std::size_t>(k) / parts, e = key.size() * (static_cast<std::size_t>(k) + 1) / parts;
      for (std::size_t i = b; i < e; ++i) {
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
      std::sort(part(static_cast<std::size_t>(k)), part(static_cast<std::size_t>(k) + 1));
    });
    for (std::size_t w = 1; w < parts; w *= 2)
      for (std::size_t k = 0; k + w < parts; k += 2 * w) std::inplace_merge(part(k), part(k + w), part(std::min(k + 2 * w, parts)));
    std::vector<Feature> sorted(features.size());
    for (std::size_t i = 0; i < key.size(); ++i) sorted[i] = features[key[i].second];
    features.swap(sorted);
  }
  // A feature decides only samples within the cap of it (truncated grids): its index box is cut
  // to them. Without the walk, polyhedra are built in the scan only (building one is a good part
  // of the work for a narrow band), and features without one are dropped there.
  pool.parallel_for_ranges(features.size(), 512, [&](int, std::size_t b, std::size_t e) {
    Shape s;
    for (std::size_t i = b; i < e; ++i) {
      Feature& f = features[i];
      f.reach = 0;
      if (!walk) {
        if (index_box(ctx, near_box(ctx, f, cap), f.lo, f.hi)) f.reach = cap;
        continue;
      }
      if (!make_shape(ctx, f, s)) continue;
      f.reach = std::min(find_reach(ctx, s, cap), cap);
      if (f.reach <= 0) continue;
      Box3 box = shape_box(s, f.reach);
      if (truncated) {
        const Box3 near = near_box(ctx, f, cap);
        box = {max(box.lo, near.lo), min(box.hi, near.hi)};
      }
      if (!index_box(ctx, box, f.lo, f.hi)) f.reach = 0;
    }
  });

  if (debug) {
    std::fprintf(stderr, "cpt reaches done   %.3f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - tstart).count());
    double sum[3] = {0, 0, 0}; std::size_t cnt[3] = {0, 0, 0}, wide[3] = {0, 0, 0}, zero[3] = {0, 0, 0};
    Shape sh;
    for (const Feature& f : features) {
      const int k = static_cast<int>(f.kind);
      if (f.reach <= 0 || !make_shape(ctx, f, sh)) { ++zero[k]; continue; }
      ++cnt[k]; sum[k] += f.reach / ctx.shell; wide[k] += sh.wide;
    }
    for (int k = 0; k < 3; ++k) std::fprintf(stderr, "kind %d: %zu used, %zu unused, %zu wide, mean reach %.2f shells\n", k, cnt[k], zero[k], wide[k], cnt[k] ? sum[k] / cnt[k] : 0.0);
  }
  // 3. Scan. Workers own slabs of slices, so that no two write the same sample, and ties go to
  // the lower feature index, so the result does not depend on the order. A feature whose slices
  // fit in its first slab (its home) and the next is scanned whole from its home: even homes
  // first, then odd ones, so that the two slabs a worker writes are written by no other worker
  // meanwhile. Longer features are scanned slab by slab, their polyhedron built again in each.
  report("scan", 0.25);
  const auto tscan = std::chrono::steady_clock::now();
  const std::size_t n = grid.size();
  const int nx = grid.counts[0], ny = grid.counts[1], nz = grid.counts[2];
  const int slabs = std::min(nx, 8 * pool.size());
  std::optional<RowScratch> rows(std::in_place, nx, ny, nz, slabs);
  if (!truncated) rows->allocate_all(pool);
  auto slab_begin = [&](int s) { return static_cast<int>(static_cast<long long>(nx) * std::min(s, slabs) / slabs); };
  std::vector<std::vector<std::uint32_t>> homes(static_cast<std::size_t>(slabs)), longs(static_cast<std::size_t>(slabs));
  for (std::uint32_t i = 0; i < features.size(); ++i) {
    const Feature& f = features[i];
    if (f.reach <= 0) continue;
    // The home: from the slab before the one the division points at (it rounds).
    int home = std::max(0, static_cast<int>(static_cast<long long>(f.lo[0]) * slabs / nx) - 1);
    while (slab_begin(home + 1) <= f.lo[0]) ++home;
    if (f.hi[0] < slab_begin(home + 2)) {
      homes[static_cast<std::size_t>(home)].push_back(i);
      continue;
    }
    for (int s = home; s < slabs && slab_begin(s) <= f.hi[0]; ++s) longs[static_cast<std::size_t>(s)].push_back(i);
  }
  if (debug) {
    std::size_t short_count = 0, long_entries = 0;
    for (int s = 0; s < slabs; ++s) short_count += homes[s].size(), long_entries += longs[s].size();
    std::fprintf(stderr, "%d slabs, %zu features within two slabs, %zu (slab, feature) pairs for the others\n", slabs,
                 short_count, long_entries);
  }
  std::atomic<std::uint64_t> evaluations{0};
  std::atomic<std::size_t> used{0};
  std::atomic<int> items_done{0};
  const auto scan_slab = [&](int s, const std::vector<std::uint32_t>& ids, bool whole) {
    Shape sh;
    std::uint64_t ev = 0;
    std::size_t built = 0;
    for (std::uint32_t id : ids) {
      const Feature& f = features[id];
      if (!make_shape(ctx, f, sh)) continue;
      built += whole || f.lo[0] >= slab_begin(s);  // counted once
      if (sh.cap) sh.add(sh.dir, sh.p[0] + sh.dir * f.reach);
      if (sh.both) sh.add(-sh.dir, sh.p[0] - sh.dir * f.reach);
      ev += scan(ctx, sh, f.reach, id, f.lo, f.hi, slab_begin(s), slab_begin(whole ? s + 2 : s + 1), *rows, s);
    }
    evaluations += ev;
    used += built;
    report("scan", 0.25 + 0.6 * (++items_done) / (2 * slabs));
  };
  for (int parity : {0, 1})
    pool.parallel_for((slabs + 1 - parity) / 2, [&](int, int h) {
      const int s = 2 * h + parity;
      scan_slab(s, homes[static_cast<std::size_t>(s)], true);
    });
  pool.parallel_for(slabs, [&](int, int s) { scan_slab(s, longs[static_cast<std::size_t>(s)], false); });
  if (debug) std::fprintf(stderr, "cpt scan took     %.3f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - tscan).count());

  // 4. Each sample's value from the feature that won it, with MeshDistance's formulas and signs.
  // Truncated: only samples within the band; the others are marked (NaN) and, row by row, given
  // +-D by the side of a band sample beside them in the row (both ends of a run agree). A
  // winner's distance is at least the scan's (for an edge, the distance to its face is at least
  // the distance to its line), so a sample whose scanned distance is beyond the band is skipped.
  report("signs", 0.85);
  const T beyond = std::numeric_limits<T>::quiet_NaN();
  const T plus = static_cast<T>(trunc), minus = static_cast<T>(-trunc);
  const auto side = [&](T v) { return v > 0 ? plus : minus; };
  const double skip2 = band * band * (1 + 1e-9);
  // A sample's side from the oracle: only where the argument at the top gives none (a grid
  // without a band sample; defensively, a run beside band samples at 0 only).
  std::atomic<std::size_t> queries{0};
  const auto oracle_side = [&](int i, int j, int k) {
    ++queries;
    const Vec3 p{ctx.coords[0][static_cast<std::size_t>(i)], ctx.coords[1][static_cast<std::size_t>(j)],
                 ctx.coords[2][static_cast<std::size_t>(k)]};
    return field.signed_distance(p) > 0 ? plus : minus;
  };
  // Truncated: rows (i, j) settled in this step (they hold a band sample); the others are left
  // to the flood fill of step 5.
  std::vector<std::uint8_t> resolved(truncated ? static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) : 0, 0);
  std::atomic<std::size_t> fallback{0}, in_band{0};
  pool.parallel_for(nx, [&](int, int i) {
    std::size_t fb = 0, nb = 0;
    for (int j = 0; j < ny; ++j) {
      const std::size_t row = grid.index(i, j, 0);
      const double* best = rows->best(i, j);
      const std::uint32_t* owner = rows->owner(i, j);
      if (!best) continue;  // truncated: a row no polyhedron reached, left to step 5
      std::size_t row_band = 0;
      for (int k = 0; k < nz; ++k) {
        const std::size_t idx = row + static_cast<std::size_t>(k);
        const std::uint32_t o = owner[k];
        if (truncated && (o == kNoOwner || best[k] > skip2)) {
          out[idx] = beyond;
          continue;
        }
        const Vec3 p{ctx.coords[0][static_cast<std::size_t>(i)], ctx.coords[1][static_cast<std::size_t>(j)],
                     ctx.coords[2][static_cast<std::size_t>(k)]};
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
        if (truncated) {
          if (!(std::fabs(v) <= band)) {
            out[idx] = beyond;
            continue;
          }
          ++row_band;
          v = std::clamp(v, -trunc, trunc);
        }
        out[idx] = static_cast<T>(v);
      }
      if (!row_band) continue;
      nb += row_band;
      // The row's runs beyond the band.
      T* r = out + row;
      int run = -1;  // first sample of the current run without a side yet
      T last = 0;    // the last band sample's value (0: none yet, or one on the surface)
      for (int k = 0; k < nz; ++k) {
        const T v = r[k];
        if (std::isnan(v)) {
          if (last != 0) r[k] = side(last);
          else if (run < 0) run = k;
          continue;
        }
        last = v;
        if (run >= 0 && v != 0) {
          std::fill(r + run, r + k, side(v));
          run = -1;
        }
      }
      if (run >= 0) std::fill(r + run, r + nz, oracle_side(i, j, run));
      resolved[static_cast<std::size_t>(i) * ny + j] = 1;
    }
    fallback += fb;
    in_band += nb;
  });
  rows.reset();

  // 5. Truncated: rows entirely beyond the band, by a flood fill over the (i, j) rows from the
  // settled ones. Such a row is one region, on the side of the samples beside it in a
  // neighbouring row.
  if (truncated) {
    report("sides", 0.95);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t r = 0; r < resolved.size(); ++r)
      if (resolved[r]) queue.push_back(r);
    if (queue.empty()) {
      // No band sample: the grid is one region on one side.
      std::fill(out, out + n, oracle_side(0, 0, 0));
    } else {
      for (std::size_t q = 0; q < queue.size(); ++q) {
        const int i = static_cast<int>(queue[q] / ny), j = static_cast<int>(queue[q] % ny);
        const T from = out[grid.index(i, j, 0)];
        const int ni[4] = {i - 1, i + 1, i, i}, nj[4] = {j, j, j - 1, j + 1};
        for (int e = 0; e < 4; ++e) {
          if (ni[e] < 0 || ni[e] >= nx || nj[e] < 0 || nj[e] >= ny) continue;
          const std::uint32_t r = static_cast<std::uint32_t>(ni[e]) * ny + nj[e];
          if (resolved[r]) continue;
          resolved[r] = 1;
          std::fill_n(out + grid.index(ni[e], nj[e], 0), nz, from != 0 ? side(from) : oracle_side(ni[e], nj[e], 0));
          queue.push_back(r);
        }
      }
    }
    stats.side_queries = queries;
  }
  stats.features = used;
  stats.evaluations = evaluations;
  stats.band_samples = in_band;
  stats.fallback_samples = fallback;
  report("done", 1);
}

template void closest_point_transform<float>(const MeshField&, const GridSpec&, ThreadPool&, float*,
                                             const MeshGridOptions&, MeshGridStats&);
template void closest_point_transform<double>(const MeshField&, const GridSpec&, ThreadPool&, double*,
                                              const MeshGridOptions&, MeshGridStats&);

}  // namespace frep::sample_detail
