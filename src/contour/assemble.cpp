// Polygons around crossing edges, their triangulation and the merge of all leaves in key order.
//
// Triangulation: a quad is split along its better diagonal; any other polygon, and a quad whose
// split folds, becomes a fan of triangles about the edge's crossing point. The fan about a point
// of the edge is intersection-free when every cell has one vertex inside it (each triangle then
// crosses the face between two neighbouring cells, and its part in a cell is a cone from the
// cell's vertex over segments of the cell's boundary that do not cross; Ju and Udeshi 2006). The
// diagonal split is not, so after splitting every vertex's star (its triangles) and every fan is
// checked: projected (onto the plane of the vertex's normal; along the edge for a fan) its
// triangles must turn the same way and go round once, or else no two of them may meet (the exact
// test behind `frep check`). At a vertex that fails, its quads become fans; if it still fails, its
// cell's vertices go to their mass points; then other positions in its cell are tried. Repeated
// until every vertex passes; coordinates are f32 values throughout, so the result holds for STL.
//
// Cells with several vertices (pieces of surface) do not fit that argument, so their polygons
// are fans, and each polygon edge between two cells, one of them with several vertices, goes
// through a point of the face between them (the mean of the midpoints of the segment's two cell
// edges, shared by the segment's two polygons). Every triangle at such a cell then lies in the
// cell, as a cone from the piece's vertex (at the centroid of its crossings) over its own curve
// on the cell's boundary, and the pieces' curves do not meet.
#include "contour/assemble.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "contour/cell_topology.hpp"
#include "frep/error.hpp"
#include "frep/mesh/tri_tri.hpp"

namespace frep::contour {
namespace {

// The four cells around an edge along `a`, counter-clockwise seen from +a (so the polygon's
// normal is +a), as offsets along the next two axes b = a+1, c = a+2 (mod 3) from the cell that
// owns the edge (the one whose low corner is the edge's low end); per cell, its local edge and
// the slots (cell_edge_face) of the faces towards the previous and the next cell.
struct Around {
  int db[4], dc[4], edge[4], kprev[4], knext[4];
};

std::array<Around, 3> make_around() {
  std::array<Around, 3> r{};
  const int db[4] = {-1, 0, 0, -1}, dc[4] = {-1, -1, 0, 0};
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    Around& A = r[static_cast<std::size_t>(a)];
    for (int i = 0; i < 4; ++i) {
      A.db[i] = db[i];
      A.dc[i] = dc[i];
      const int corner = (db[i] == -1 ? 1 << b : 0) | (dc[i] == -1 ? 1 << c : 0);
      A.edge[i] = cell_edge(a, corner);
    }
    for (int i = 0; i < 4; ++i) {
      auto slot_towards = [&](int j) {
        const int d = db[j] != db[i] ? b : c;
        const int side = (d == b ? db[j] > db[i] : dc[j] > dc[i]) ? 1 : 0;
        const int face = 2 * d + side;
        const int k = cell_edge_face(A.edge[i], 0) == face ? 0 : 1;
        FREP_ASSERT(cell_edge_face(A.edge[i], k) == face, "face not at edge");
        return k;
      };
      A.kprev[i] = slot_towards((i + 3) % 4);
      A.knext[i] = slot_towards((i + 1) % 4);
    }
  }
  return r;
}

const std::array<Around, 3> kAround = make_around();

// The polygon of one crossing edge, outward: 4 to 8 dual vertices, and the face points between
// some of them (12 entries at most).
struct Poly {
  enum Mode : std::uint8_t { SplitA, SplitB, Fan };  // A: diagonal 0-2, B: diagonal 1-3 (quads)
  std::uint32_t v[12];
  std::uint8_t n = 0;
  Mode mode = Fan;
  std::uint8_t axis = 0;  // the edge's axis
  std::int8_t dir = 1;    // outward along +axis (1) or -axis (-1)
  Vec3 center;            // a point of the edge near its crossing: the fan's center
};

// Global id of a grid edge: its low corner and axis.
std::uint64_t edge_id(const MeshGrid& g, const int corner[3], int axis) {
  return ((static_cast<std::uint64_t>(corner[2]) * static_cast<std::uint64_t>(g.n[1] + 1) + static_cast<std::uint64_t>(corner[1])) *
              static_cast<std::uint64_t>(g.n[0] + 1) +
          static_cast<std::uint64_t>(corner[0])) *
             3 +
         static_cast<std::uint64_t>(axis);
}
Vec3 edge_midpoint(const MeshGrid& g, std::uint64_t id) {
  const int axis = static_cast<int>(id % 3);
  id /= 3;
  const int c[3] = {static_cast<int>(id % static_cast<std::uint64_t>(g.n[0] + 1)),
                    static_cast<int>((id / static_cast<std::uint64_t>(g.n[0] + 1)) % static_cast<std::uint64_t>(g.n[1] + 1)),
                    static_cast<int>(id / static_cast<std::uint64_t>(g.n[0] + 1) / static_cast<std::uint64_t>(g.n[1] + 1))};
  Vec3 p{g.coord(0, c[0]), g.coord(1, c[1]), g.coord(2, c[2])};
  p[axis] = 0.5 * (p[axis] + g.coord(axis, c[axis] + 1));
  return p;
}

constexpr std::uint32_t kRouted = 0x80000000u;  // in a leaf's polygons: index of a face point

Vec3 unit(const Vec3& v) {
  const double l = length(v);
  return l > 0 ? v / l : Vec3{};
}

// Appends the triangles of `p` (with `center` the index of its fan center) that contain vertex
// `only` (all if `only` is ~0).
template <class F>
void triangles_of(const Poly& p, std::uint32_t center, std::uint32_t only, F&& emit) {
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (only == ~0u || a == only || b == only || c == only) emit(a, b, c);
  };
  if (p.mode == Poly::SplitA) {
    tri(p.v[0], p.v[1], p.v[2]);
    tri(p.v[0], p.v[2], p.v[3]);
  } else if (p.mode == Poly::SplitB) {
    tri(p.v[0], p.v[1], p.v[3]);
    tri(p.v[1], p.v[2], p.v[3]);
  } else {
    for (int i = 0; i < p.n; ++i) tri(p.v[i], p.v[(i + 1) % p.n], center);
  }
}

}  // namespace

std::uint64_t leaf_key(const std::array<int, 3>& lo, int leaf_size) {
  return (static_cast<std::uint64_t>(lo[2] / leaf_size) << 42) | (static_cast<std::uint64_t>(lo[1] / leaf_size) << 21) |
         static_cast<std::uint64_t>(lo[0] / leaf_size);
}

TriMesh assemble(const std::vector<LeafRecord*>& leaves, const MeshGrid& grid, int leaf_size, ThreadPool& pool,
                 std::size_t* unresolved) {
  std::vector<std::uint64_t> keys(leaves.size());
  std::uint64_t nv64 = 0;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    keys[i] = leaves[i]->key;
    FREP_ASSERT(i == 0 || keys[i] > keys[i - 1], "leaves not sorted");
    leaves[i]->vertex_offset = static_cast<std::uint32_t>(nv64);
    nv64 += leaves[i]->positions.size();
  }
  FREP_ASSERT(nv64 < 0x7fffffffu, "too many vertices");
  const auto nv = static_cast<std::uint32_t>(nv64);
  auto find = [&](std::uint64_t key) -> LeafRecord* {
    auto it = std::lower_bound(keys.begin(), keys.end(), key);
    return it != keys.end() && *it == key ? leaves[static_cast<std::size_t>(it - keys.begin())] : nullptr;
  };

  // All vertices, in leaf order.
  std::vector<Vec3> pos(nv), mass(nv), nrm(nv);
  std::vector<std::uint8_t> piece(nv);
  for (const LeafRecord* r : leaves)
    for (std::size_t i = 0; i < r->positions.size(); ++i) {
      pos[r->vertex_offset + i] = r->positions[i];
      mass[r->vertex_offset + i] = r->mass[i];
      nrm[r->vertex_offset + i] = Vec3(r->normals[i]);
      piece[r->vertex_offset + i] = r->piece[i];
    }

  // Polygons, per leaf, of the edges its cells own; face points as keys (edge pairs) per leaf.
  struct RouteKey {
    std::uint64_t e0, e1;
    bool operator<(const RouteKey& o) const { return e0 != o.e0 ? e0 < o.e0 : e1 < o.e1; }
    bool operator==(const RouteKey& o) const { return e0 == o.e0 && e1 == o.e1; }
  };
  // One polygon per crossing edge a cell owns: counted first, so that every leaf writes its
  // polygons straight into its slice of one array.
  std::vector<std::size_t> poly_first(leaves.size() + 1, 0);
  for (std::size_t li = 0; li < leaves.size(); ++li) {
    std::size_t n = 0;
    for (const SurfaceCell& c : leaves[li]->cells)
      for (float t : c.t) n += !std::isnan(t);
    poly_first[li + 1] = poly_first[li] + n;
  }
  std::vector<Poly> polys(poly_first.back());
  std::vector<std::vector<RouteKey>> leaf_routes(leaves.size());
  pool.parallel_for(static_cast<int>(leaves.size()), [&](int, int li) {
    const LeafRecord& R = *leaves[static_cast<std::size_t>(li)];
    Poly* out = polys.data() + poly_first[static_cast<std::size_t>(li)];
    std::vector<RouteKey>& routes = leaf_routes[static_cast<std::size_t>(li)];
    // The leaf and its lower neighbours: nb[dz][dy][dx] for offsets -1 (index 0) and 0 (index 1).
    const LeafRecord* nb[2][2][2];
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const std::array<int, 3> lo{R.box.lo[0] + (dx - 1) * leaf_size, R.box.lo[1] + (dy - 1) * leaf_size,
                                      R.box.lo[2] + (dz - 1) * leaf_size};
          nb[dz][dy][dx] = (lo[0] < 0 || lo[1] < 0 || lo[2] < 0) ? nullptr : find(leaf_key(lo, leaf_size));
        }
    auto cell_at = [&](const int g[3], const LeafRecord*& rec) -> const SurfaceCell& {
      rec = nb[g[2] < R.box.lo[2] ? 0 : 1][g[1] < R.box.lo[1] ? 0 : 1][g[0] < R.box.lo[0] ? 0 : 1];
      FREP_ASSERT(rec != nullptr, "a cell around a crossing is in no leaf");
      const std::size_t lx = static_cast<std::size_t>(g[0] - rec->box.lo[0]),
                        ly = static_cast<std::size_t>(g[1] - rec->box.lo[1]),
                        lz = static_cast<std::size_t>(g[2] - rec->box.lo[2]);
      const std::uint16_t slot =
          rec->cell_slot[lx + static_cast<std::size_t>(rec->box.extent(0)) * (ly + static_cast<std::size_t>(rec->box.extent(1)) * lz)];
      FREP_ASSERT(slot != kNoCell, "a cell around a crossing has no surface");
      return rec->cells[slot];
    };

    const int ex = R.box.extent(0), ey = R.box.extent(1), ez = R.box.extent(2);
    for (int z = 0; z < ez; ++z)
      for (int y = 0; y < ey; ++y)
        for (int x = 0; x < ex; ++x) {
          const std::uint16_t slot =
              R.cell_slot[static_cast<std::size_t>(x) + static_cast<std::size_t>(ex) * (y + static_cast<std::size_t>(ey) * z)];
          if (slot == kNoCell) continue;
          const SurfaceCell& owner = R.cells[slot];
          const int og[3] = {R.box.lo[0] + x, R.box.lo[1] + y, R.box.lo[2] + z};
          for (int a = 0; a < 3; ++a) {
            if (std::isnan(owner.t[a])) continue;
            const Around& A = kAround[static_cast<std::size_t>(a)];
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            // The four cells: their vertices at this crossing and whether they have several.
            std::uint32_t vs[4][2];
            int nvs[4];
            bool multi[4];
            int cells[4][3];
            const CellTopology* topos[4];
            for (int i = 0; i < 4; ++i) {
              int* g = cells[i];
              g[0] = og[0], g[1] = og[1], g[2] = og[2];
              g[b] += A.db[i];
              g[c] += A.dc[i];
              const LeafRecord* rec = nullptr;
              const SurfaceCell& cell = cell_at(g, rec);
              const CellTopology& topo = cell_topology(cell.config, cell.decisions);
              topos[i] = &topo;
              const std::uint8_t vp = topo.vertex_at[A.edge[i]][A.kprev[i]];
              const std::uint8_t vn = topo.vertex_at[A.edge[i]][A.knext[i]];
              FREP_ASSERT(vp != kNoCellVertex && vn != kNoCellVertex, "no vertex for a crossing");
              // One vertex, or two where the crossing ends a chord that split a piece of surface.
              nvs[i] = 0;
              vs[i][nvs[i]++] = rec->vertex_offset + cell.first_vertex + vp;
              if (vn != vp) vs[i][nvs[i]++] = rec->vertex_offset + cell.first_vertex + vn;
              multi[i] = topo.vertices > 1;
            }
            Poly p;
            bool routed = false;
            for (int i = 0; i < 4; ++i) {
              for (int k = 0; k < nvs[i]; ++k) p.v[p.n++] = vs[i][k];
              const int j = (i + 1) % 4;
              if (!multi[i] && !multi[j]) continue;
              // Through the face between cells i and j: the point of the segment that ends here.
              const int e = A.edge[i], other = topos[i]->partner[e][A.knext[i]];
              FREP_ASSERT(other >= 0, "segment without an end");
              int lowc[3];
              const int oc = cell_edge_corner(other, 0);
              for (int d = 0; d < 3; ++d) lowc[d] = cells[i][d] + ((oc >> d) & 1);
              const std::uint64_t k0 = edge_id(grid, og, a), k1 = edge_id(grid, lowc, other / 4);
              p.v[p.n++] = kRouted | static_cast<std::uint32_t>(routes.size());
              routes.push_back({std::min(k0, k1), std::max(k0, k1)});
              routed = true;
            }
            // Outward: from the inside end of the edge to the outside end.
            const bool low_inside = owner.config & 1;
            if (!low_inside) std::reverse(p.v, p.v + p.n);
            // The fan center: on the edge at the crossing (an f32 value), kept off the edge's ends
            // so that it differs from every other vertex (an edge spans 64 f32 steps at least).
            const double t = std::clamp(static_cast<double>(owner.t[a]), 0.05, 0.95);
            p.axis = static_cast<std::uint8_t>(a);
            p.dir = low_inside ? 1 : -1;
            p.center = Vec3{grid.coord(0, og[0]), grid.coord(1, og[1]), grid.coord(2, og[2])};
            p.center[a] = round_f32(p.center[a] + t * (grid.coord(a, og[a] + 1) - p.center[a]));
            if (p.n == 4 && !routed) {
              // The better diagonal: the one that stays in the tangent planes at its ends (along a
              // sharp edge rather than across it), unless only the other keeps both triangles
              // facing along the edge, or only the other avoids a sliver (three vertices along one
              // sharp edge make a triangle of no area).
              Vec3 dir;
              dir[a] = low_inside ? 1 : -1;
              const Vec3 q[4] = {pos[p.v[0]], pos[p.v[1]], pos[p.v[2]], pos[p.v[3]]};
              const Vec3 n[4] = {nrm[p.v[0]], nrm[p.v[1]], nrm[p.v[2]], nrm[p.v[3]]};
              auto facing = [&](int i, int j, int k) { return dot(unit(cross(q[j] - q[i], q[k] - q[i])), dir); };
              auto deviation = [&](int i, int j) {
                const Vec3 d = q[j] - q[i];
                return std::fabs(dot(d, n[i])) + std::fabs(dot(d, n[j]));
              };
              auto sliver = [&](int i, int j, int k) {
                const Vec3 e0 = q[j] - q[i], e1 = q[k] - q[i], e2 = q[k] - q[j];
                return length(cross(e0, e1)) <= 1e-6 * std::max({length2(e0), length2(e1), length2(e2)});
              };
              const double fa = std::min(facing(0, 1, 2), facing(0, 2, 3));
              const double fb = std::min(facing(0, 1, 3), facing(1, 2, 3));
              const bool sa = sliver(0, 1, 2) || sliver(0, 2, 3), sb = sliver(0, 1, 3) || sliver(1, 2, 3);
              const bool use_a = sa != sb                ? sb
                                 : (fa > 0) != (fb > 0) ? fa > 0
                                                         : deviation(0, 2) <= deviation(1, 3);
              p.mode = use_a ? Poly::SplitA : Poly::SplitB;
            }
            *out++ = p;
          }
        }
    FREP_ASSERT(out == polys.data() + poly_first[static_cast<std::size_t>(li) + 1], "polygon count");
  });

  // Face points: one vertex per key, numbered after the dual vertices in key order.
  std::vector<RouteKey> keys_all;
  for (const auto& r : leaf_routes) keys_all.insert(keys_all.end(), r.begin(), r.end());
  std::sort(keys_all.begin(), keys_all.end());
  keys_all.erase(std::unique(keys_all.begin(), keys_all.end()), keys_all.end());
  FREP_ASSERT(nv64 + keys_all.size() < 0x7fffffffu, "too many vertices");
  std::vector<Vec3> route_pos(keys_all.size());
  for (std::size_t i = 0; i < keys_all.size(); ++i) {
    const Vec3 m = (edge_midpoint(grid, keys_all[i].e0) + edge_midpoint(grid, keys_all[i].e1)) * 0.5;
    route_pos[i] = round_f32(m);
  }
  if (!keys_all.empty())
    for (std::size_t li = 0; li < leaves.size(); ++li) {
      if (leaf_routes[li].empty()) continue;
      for (std::size_t pi = poly_first[li]; pi < poly_first[li + 1]; ++pi) {
        Poly& p = polys[pi];
        for (int i = 0; i < p.n; ++i)
          if (p.v[i] & kRouted) {
            const RouteKey& k = leaf_routes[li][p.v[i] & ~kRouted];
            p.v[i] = nv + static_cast<std::uint32_t>(std::lower_bound(keys_all.begin(), keys_all.end(), k) - keys_all.begin());
          }
      }
    }
  auto position = [&](std::uint32_t id) -> const Vec3& { return id < nv ? pos[id] : route_pos[id - nv]; };

  // Vertex -> polygons (CSR).
  std::vector<std::uint32_t> first(static_cast<std::size_t>(nv) + 1, 0), incident;
  for (const Poly& p : polys)
    for (int i = 0; i < p.n; ++i)
      if (p.v[i] < nv) ++first[p.v[i] + 1];
  for (std::uint32_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  incident.resize(first[nv]);
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t pi = 0; pi < polys.size(); ++pi)
      for (int i = 0; i < polys[pi].n; ++i)
        if (polys[pi].v[i] < nv) incident[fill[polys[pi].v[i]]++] = pi;
  }

  // Star check: does the fan of triangles around v project, onto the plane of their summed
  // normal, as wedges that all turn the same way and go round exactly once?
  // Do the triangles about their first corner, projected to 2D by `proj`, turn the same way
  // (counter-clockwise, each by less than half a turn and clearly more than none) and go round
  // exactly once? The turns are counted as the triangles that cross the ray along +x from below.
  // Nearly flat turns are left to the exact test (a sliver may be folded).
  auto fan_winds_once = [](const auto& tris, auto&& proj) {
    int crossings = 0;
    for (const auto& t : tris) {
      const auto [ax, ay] = proj(t.p[1] - t.p[0]);
      const auto [bx, by] = proj(t.p[2] - t.p[0]);
      if (!(ax * by - ay * bx > 1e-9 * std::sqrt((ax * ax + ay * ay) * (bx * bx + by * by)))) return false;
      crossings += ay < 0 && by >= 0;
    }
    return crossings == 1;
  };

  // Star check. The quick test: the triangles at v, projected onto the plane of their summed
  // normal, are wedges that all turn the same way and go round exactly once (then no two of them
  // meet but along their shared edges). Stars it cannot vouch for (a cone over a saddle-shaped
  // curve, say) get the exact pairwise triangle test instead.
  struct StarTri {
    unsigned id[3];
    Vec3 p[3];
  };
  auto star_ok = [&](std::uint32_t v, std::vector<StarTri>& tris) {
    tris.clear();
    for (std::uint32_t k = first[v]; k < first[v + 1]; ++k) {
      const std::uint32_t pi = incident[k];
      const Poly& p = polys[pi];
      // A fan center's id: unique to its polygon, above every vertex id.
      const std::uint32_t center = 0x80000000u | pi;
      triangles_of(p, center, v, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        auto at = [&](std::uint32_t i) { return i == center ? p.center : position(i); };
        // Rotated so that v comes first.
        const std::uint32_t r[3] = {a == v ? a : (b == v ? b : c), a == v ? b : (b == v ? c : a), a == v ? c : (b == v ? a : b)};
        tris.push_back({{r[0], r[1], r[2]}, {at(r[0]), at(r[1]), at(r[2])}});
      });
    }
    // Projected along the vertex's normal (from its crossings), else along the triangles' mean.
    auto winds_along = [&](const Vec3& n) {
      if (n == Vec3{}) return false;
      const Vec3 u = unit(std::fabs(n.x) < 0.9 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0}));
      const Vec3 w = cross(n, u);
      return fan_winds_once(tris, [&](const Vec3& d) { return std::pair{dot(d, u), dot(d, w)}; });
    };
    if (winds_along(nrm[v])) return true;
    Vec3 nsum;
    for (const StarTri& t : tris) nsum += unit(cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
    if (winds_along(unit(nsum))) return true;
    for (std::size_t i = 0; i < tris.size(); ++i) {
      if (length(cross(tris[i].p[1] - tris[i].p[0], tris[i].p[2] - tris[i].p[0])) == 0) return false;
      for (std::size_t j = i + 1; j < tris.size(); ++j) {
        if (length(cross(tris[j].p[1] - tris[j].p[0], tris[j].p[2] - tris[j].p[0])) == 0) return false;
        const Contact c = classify_triangle_pair(tris[i].p, tris[i].id, tris[j].p, tris[j].id);
        if (c == Contact::Cross || c == Contact::Overlap) return false;
      }
    }
    return true;
  };

  // A fan polygon must not fold about its center: seen along the edge, its triangles turn the
  // same way and go round once (or, failing that quick test, no two of them meet).
  auto fan_ok = [&](std::uint32_t pi, std::vector<StarTri>& tris) {
    const Poly& p = polys[pi];
    if (p.mode != Poly::Fan) return true;
    tris.clear();
    const std::uint32_t center = 0x80000000u | pi;
    triangles_of(p, center, ~0u, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      tris.push_back({{c, a, b}, {p.center, position(a), position(b)}});
    });
    const int u = (p.axis + 1) % 3, w = (p.axis + 2) % 3;
    const double dir = p.dir;
    if (fan_winds_once(tris, [&](const Vec3& d) { return std::pair{d[u], dir * d[w]}; })) return true;
    for (std::size_t i = 0; i < tris.size(); ++i) {
      if (length(cross(tris[i].p[1] - tris[i].p[0], tris[i].p[2] - tris[i].p[0])) == 0) return false;
      for (std::size_t j = i + 1; j < tris.size(); ++j) {
        const Contact c = classify_triangle_pair(tris[i].p, tris[i].id, tris[j].p, tris[j].id);
        if (c == Contact::Cross || c == Contact::Overlap) return false;
      }
    }
    return true;
  };
  // A dual vertex passes when its star does and no fan at it folds.
  auto vertex_ok = [&](std::uint32_t v, std::vector<StarTri>& tris) {
    if (!star_ok(v, tris)) return false;
    for (std::uint32_t k = first[v]; k < first[v + 1]; ++k)
      if (!fan_ok(incident[k], tris)) return false;
    return true;
  };

  // The cell a dual vertex is in (strictly inside), shrunk by the inset.
  auto cell_box = [&](const Vec3& p) {
    Box3 b;
    for (int a = 0; a < 3; ++a) {
      const auto& c = grid.grid.coords[static_cast<std::size_t>(a)];
      auto it = std::upper_bound(c.begin(), c.end(), static_cast<float>(p[a]));
      std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - c.begin())) - 1;
      i = std::min(i, c.size() - 2);
      if (p[a] < c[i] && i > 0) --i;
      if (p[a] > c[i + 1] && i + 2 < c.size()) ++i;
      b.lo[a] = c[i] + kVertexInset * grid.h;
      b.hi[a] = c[i + 1] - kVertexInset * grid.h;
    }
    return b;
  };
  // Last resort for a vertex whose star or fans fail with every polygon a fan and its cell at
  // its mass points: other positions in its cell, nearest first (towards the centroid of its
  // star's other corners, then a lattice over the cell), accepted when its own checks and those
  // of the vertices it shares triangles with all pass.
  auto relocate = [&](std::uint32_t v, std::vector<StarTri>& tris) {
    star_ok(v, tris);
    if (tris.empty()) return false;
    Vec3 centroid;
    for (const StarTri& t : tris) centroid += (t.p[1] + t.p[2]) * 0.5;
    centroid = centroid / static_cast<double>(tris.size());
    const Vec3 orig = pos[v];
    const Box3 box = cell_box(orig);
    std::vector<Vec3> candidates;
    for (double w : {1.0, 0.5, 0.75, 0.25}) candidates.push_back(to_f32_inside(orig + (centroid - orig) * w, box));
    std::vector<Vec3> lattice;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        for (int k = 0; k < 5; ++k)
          lattice.push_back(box.lo + Vec3{(box.hi.x - box.lo.x) * (0.1 + 0.2 * i), (box.hi.y - box.lo.y) * (0.1 + 0.2 * j),
                                          (box.hi.z - box.lo.z) * (0.1 + 0.2 * k)});
    for (Vec3& c : lattice) c = to_f32_inside(c, box);
    std::stable_sort(lattice.begin(), lattice.end(),
                     [&](const Vec3& a, const Vec3& b) { return length2(a - orig) < length2(b - orig); });
    candidates.insert(candidates.end(), lattice.begin(), lattice.end());
    for (const Vec3& c : candidates) {
      pos[v] = c;
      bool ok = vertex_ok(v, tris);
      for (std::uint32_t k = first[v]; k < first[v + 1] && ok; ++k) {
        const Poly& p = polys[incident[k]];
        for (int i = 0; i < p.n && ok; ++i)
          if (p.v[i] < nv && p.v[i] != v) ok = vertex_ok(p.v[i], tris);
      }
      if (ok) return true;
    }
    pos[v] = orig;
    return false;
  };

  std::vector<std::uint32_t> dirty(nv);
  for (std::uint32_t v = 0; v < nv; ++v) dirty[v] = v;
  std::vector<StarTri> scratch;
  std::vector<std::uint32_t> stuck;  // vertices no repair could fix
  std::vector<char> moved(nv, 0), bad(nv, 0), mark(nv, 0);
  for (int round = 0; round < 8 && !dirty.empty(); ++round) {
    pool.parallel_for_ranges(dirty.size(), 4096, [&](int, std::size_t b, std::size_t e) {
      std::vector<StarTri> tris;
      for (std::size_t i = b; i < e; ++i) bad[dirty[i]] = !vertex_ok(dirty[i], tris);
    });
    // Repairs in vertex order (deterministic whatever the thread count).
    std::vector<std::uint32_t> next;
    auto touch = [&](std::uint32_t pi) {
      const Poly& p = polys[pi];
      for (int i = 0; i < p.n; ++i)
        if (p.v[i] < nv && !mark[p.v[i]]) mark[p.v[i]] = 1, next.push_back(p.v[i]);
    };
    for (std::uint32_t v : dirty) {
      if (!bad[v]) continue;
      bad[v] = 0;
      bool changed = false;
      for (std::uint32_t k = first[v]; k < first[v + 1]; ++k) {
        Poly& p = polys[incident[k]];
        if (p.mode != Poly::Fan) {
          p.mode = Poly::Fan;
          touch(incident[k]);
          changed = true;
        }
      }
      if (changed) continue;
      // Every polygon at v is a fan already: back to the mass points of v's cell.
      const std::uint32_t cell_first = v - (piece[v] & 15u), count = piece[v] >> 4;
      if (moved[cell_first] || count > 1) {
        // (Cells with several vertices have them at their mass points already.)
        if (relocate(v, scratch))
          for (std::uint32_t k = first[v]; k < first[v + 1]; ++k) touch(incident[k]);
        else
          stuck.push_back(v);
        continue;
      }
      moved[cell_first] = 1;
      for (std::uint32_t u = cell_first; u < cell_first + count; ++u) {
        pos[u] = mass[u];
        for (std::uint32_t k = first[u]; k < first[u + 1]; ++k) touch(incident[k]);
      }
    }
    for (std::uint32_t v : next) mark[v] = 0;
    std::sort(next.begin(), next.end());
    dirty = std::move(next);
  }
  // What still fails (after the last round's repairs, or beyond the rounds).
  stuck.insert(stuck.end(), dirty.begin(), dirty.end());
  std::sort(stuck.begin(), stuck.end());
  stuck.erase(std::unique(stuck.begin(), stuck.end()), stuck.end());
  if (unresolved) {
    *unresolved = 0;
    for (std::uint32_t v : stuck) *unresolved += !vertex_ok(v, scratch);
  }

  // Output: the vertices, then the fan centers in polygon order; triangles in polygon order.
  TriMesh mesh;
  std::uint64_t fans = 0, tris = 0;
  for (const Poly& p : polys) {
    fans += p.mode == Poly::Fan;
    tris += p.mode == Poly::Fan ? p.n : 2;
  }
  FREP_ASSERT(nv64 + route_pos.size() + fans < 0xffffffffu, "too many vertices");
  mesh.vertices = std::move(pos);
  mesh.vertices.reserve(static_cast<std::size_t>(nv64 + route_pos.size() + fans));
  mesh.vertices.insert(mesh.vertices.end(), route_pos.begin(), route_pos.end());
  mesh.triangles.reserve(static_cast<std::size_t>(tris));
  for (const Poly& p : polys) {
    std::uint32_t center = ~0u;
    if (p.mode == Poly::Fan) {
      center = static_cast<std::uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(p.center);
    }
    triangles_of(p, center, ~0u, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { mesh.add_triangle(a, b, c); });
  }
  return mesh;
}

}  // namespace frep::contour
