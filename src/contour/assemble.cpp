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
//
// The steps are declared, one comment each, in assemble_steps.hpp.
#include "contour/assemble.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "contour/assemble_steps.hpp"
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

Vec3 unit(const Vec3& v) {
  const double l = length(v);
  return l > 0 ? v / l : Vec3{};
}

// A leaf and its lower neighbours (those that hold the other cells around the edges it owns).
class Neighbourhood {
 public:
  Neighbourhood(const LeafRecord& leaf, const std::vector<LeafRecord*>& leaves, const std::vector<std::uint64_t>& keys,
                int leaf_size)
      : leaf_(leaf) {
    auto find = [&](std::uint64_t key) -> const LeafRecord* {
      auto it = std::lower_bound(keys.begin(), keys.end(), key);
      return it != keys.end() && *it == key ? leaves[static_cast<std::size_t>(it - keys.begin())] : nullptr;
    };
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const std::array<int, 3> lo{leaf.box.lo[0] + (dx - 1) * leaf_size, leaf.box.lo[1] + (dy - 1) * leaf_size,
                                      leaf.box.lo[2] + (dz - 1) * leaf_size};
          nb_[dz][dy][dx] = (lo[0] < 0 || lo[1] < 0 || lo[2] < 0) ? nullptr : find(leaf_key(lo, leaf_size));
        }
  }
  // The surface cell at grid index g (one cell lower than the leaf at most), and its leaf.
  const SurfaceCell& cell_at(const int g[3], const LeafRecord*& rec) const {
    rec = nb_[g[2] < leaf_.box.lo[2] ? 0 : 1][g[1] < leaf_.box.lo[1] ? 0 : 1][g[0] < leaf_.box.lo[0] ? 0 : 1];
    FREP_ASSERT(rec != nullptr, "a cell around a crossing is in no leaf");
    const std::size_t lx = static_cast<std::size_t>(g[0] - rec->box.lo[0]),
                      ly = static_cast<std::size_t>(g[1] - rec->box.lo[1]),
                      lz = static_cast<std::size_t>(g[2] - rec->box.lo[2]);
    const std::uint16_t slot =
        rec->cell_slot[lx + static_cast<std::size_t>(rec->box.extent(0)) * (ly + static_cast<std::size_t>(rec->box.extent(1)) * lz)];
    FREP_ASSERT(slot != kNoCell, "a cell around a crossing has no surface");
    return rec->cells[slot];
  }

 private:
  const LeafRecord& leaf_;
  const LeafRecord* nb_[2][2][2];  // [dz][dy][dx] for offsets -1 (index 0) and 0 (index 1)
};

// The polygon of the crossing edge along `a` at grid corner `og`, owned by cell `owner`: the
// vertices of the four cells around it at this crossing, face points (appended to `keys`) where
// a cell has several vertices, oriented outward, with its fan center and, for a quad, a diagonal.
EdgePolygon polygon_around_edge(const Assembly& as, const Neighbourhood& nb, const int og[3], int a,
                                const SurfaceCell& owner, std::vector<FacePointKey>& keys) {
  const MeshGrid& grid = as.grid;
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
    const SurfaceCell& cell = nb.cell_at(g, rec);
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
  EdgePolygon p;
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
    p.v[p.n++] = kRouted | static_cast<std::uint32_t>(keys.size());
    keys.push_back({std::min(k0, k1), std::max(k0, k1)});
    routed = true;
  }
  // Outward: from the inside end of the edge to the outside end.
  const bool low_inside = owner.config & 1;
  if (!low_inside) std::reverse(p.v, p.v + p.n);
  // The fan center: on the edge at the crossing (an f32 value), kept off the edge's ends so that
  // it differs from every other vertex (an edge spans 64 f32 steps at least).
  const double t = std::clamp(static_cast<double>(owner.t[a]), 0.05, 0.95);
  p.axis = static_cast<std::uint8_t>(a);
  p.dir = low_inside ? 1 : -1;
  p.center = Vec3{grid.coord(0, og[0]), grid.coord(1, og[1]), grid.coord(2, og[2])};
  p.center[a] = round_f32(p.center[a] + t * (grid.coord(a, og[a] + 1) - p.center[a]));
  if (p.n == 4 && !routed) {
    Vec3 outward;
    outward[a] = low_inside ? 1 : -1;
    const Vec3 q[4] = {as.pos[p.v[0]], as.pos[p.v[1]], as.pos[p.v[2]], as.pos[p.v[3]]};
    const Vec3 n[4] = {as.nrm[p.v[0]], as.nrm[p.v[1]], as.nrm[p.v[2]], as.nrm[p.v[3]]};
    p.mode = choose_diagonal(q, n, outward);
  }
  return p;
}

// The polygons of the crossing edges that the cells of `leaf` own, written from `fp.first_polygon` on.
void polygons_of_leaf(Assembly& as, const Neighbourhood& nb, const LeafRecord& leaf, LeafFacePoints& fp) {
  EdgePolygon* out = as.polys.data() + fp.first_polygon;
  const int ex = leaf.box.extent(0), ey = leaf.box.extent(1), ez = leaf.box.extent(2);
  for (int z = 0; z < ez; ++z)
    for (int y = 0; y < ey; ++y)
      for (int x = 0; x < ex; ++x) {
        const std::uint16_t slot =
            leaf.cell_slot[static_cast<std::size_t>(x) + static_cast<std::size_t>(ex) * (y + static_cast<std::size_t>(ey) * z)];
        if (slot == kNoCell) continue;
        const SurfaceCell& owner = leaf.cells[slot];
        const int og[3] = {leaf.box.lo[0] + x, leaf.box.lo[1] + y, leaf.box.lo[2] + z};
        for (int a = 0; a < 3; ++a)
          if (!std::isnan(owner.t[a])) *out++ = polygon_around_edge(as, nb, og, a, owner, fp.keys);
      }
  FREP_ASSERT(out == as.polys.data() + fp.end_polygon, "polygon count");
}

}  // namespace

std::uint64_t leaf_key(const std::array<int, 3>& lo, int leaf_size) {
  return (static_cast<std::uint64_t>(lo[2] / leaf_size) << 42) | (static_cast<std::uint64_t>(lo[1] / leaf_size) << 21) |
         static_cast<std::uint64_t>(lo[0] / leaf_size);
}

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

void gather_vertices(Assembly& as, const std::vector<LeafRecord*>& leaves) {
  std::uint64_t nv = 0;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    FREP_ASSERT(i == 0 || leaves[i]->key > leaves[i - 1]->key, "leaves not sorted");
    leaves[i]->vertex_offset = static_cast<std::uint32_t>(nv);
    nv += leaves[i]->positions.size();
  }
  FREP_ASSERT(nv < 0x7fffffffu, "too many vertices");
  as.dual = static_cast<std::uint32_t>(nv);
  as.pos.resize(nv), as.mass.resize(nv), as.nrm.resize(nv), as.piece.resize(nv);
  for (const LeafRecord* r : leaves)
    for (std::size_t i = 0; i < r->positions.size(); ++i) {
      as.pos[r->vertex_offset + i] = r->positions[i];
      as.mass[r->vertex_offset + i] = r->mass[i];
      as.nrm[r->vertex_offset + i] = Vec3(r->normals[i]);
      as.piece[r->vertex_offset + i] = r->piece[i];
    }
}

std::vector<LeafFacePoints> collect_polygons(Assembly& as, const std::vector<LeafRecord*>& leaves, int leaf_size,
                                             ThreadPool& pool) {
  // Counted first, so that every leaf writes its polygons straight into its slice of one array.
  std::vector<LeafFacePoints> fps(leaves.size());
  std::vector<std::uint64_t> keys(leaves.size());
  std::size_t total = 0;
  for (std::size_t li = 0; li < leaves.size(); ++li) {
    keys[li] = leaves[li]->key;
    fps[li].first_polygon = total;
    for (const SurfaceCell& c : leaves[li]->cells)
      for (float t : c.t) total += !std::isnan(t);
    fps[li].end_polygon = total;
  }
  as.polys.assign(total, EdgePolygon{});
  pool.parallel_for(static_cast<int>(leaves.size()), [&](int, int li) {
    const LeafRecord& leaf = *leaves[static_cast<std::size_t>(li)];
    polygons_of_leaf(as, Neighbourhood(leaf, leaves, keys, leaf_size), leaf, fps[static_cast<std::size_t>(li)]);
  });
  return fps;
}

EdgePolygon::Mode choose_diagonal(const Vec3 q[4], const Vec3 n[4], const Vec3& outward) {
  // The diagonal that stays in the tangent planes at its ends (along a sharp edge rather than
  // across it), unless only the other keeps both triangles facing along the edge, or only the
  // other avoids a sliver (three vertices along one sharp edge make a triangle of no area).
  auto facing = [&](int i, int j, int k) { return dot(unit(cross(q[j] - q[i], q[k] - q[i])), outward); };
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
  return use_a ? EdgePolygon::SplitA : EdgePolygon::SplitB;
}

void number_face_points(Assembly& as, const std::vector<LeafFacePoints>& leaves) {
  std::vector<FacePointKey> all;
  for (const LeafFacePoints& l : leaves) all.insert(all.end(), l.keys.begin(), l.keys.end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  FREP_ASSERT(std::uint64_t{as.dual} + all.size() < 0x7fffffffu, "too many vertices");
  as.face_points.resize(all.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    as.face_points[i] = round_f32((edge_midpoint(as.grid, all[i].e0) + edge_midpoint(as.grid, all[i].e1)) * 0.5);
  if (all.empty()) return;
  for (const LeafFacePoints& l : leaves) {
    if (l.keys.empty()) continue;
    for (std::size_t pi = l.first_polygon; pi < l.end_polygon; ++pi) {
      EdgePolygon& p = as.polys[pi];
      for (int i = 0; i < p.n; ++i)
        if (p.v[i] & kRouted) {
          const FacePointKey& k = l.keys[p.v[i] & ~kRouted];
          p.v[i] = as.dual + static_cast<std::uint32_t>(std::lower_bound(all.begin(), all.end(), k) - all.begin());
        }
    }
  }
}

void index_incident_polygons(Assembly& as) {
  const std::uint32_t nv = as.dual;
  as.first.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (const EdgePolygon& p : as.polys)
    for (int i = 0; i < p.n; ++i)
      if (p.v[i] < nv) ++as.first[p.v[i] + 1];
  for (std::uint32_t v = 0; v < nv; ++v) as.first[v + 1] += as.first[v];
  as.incident.resize(as.first[nv]);
  std::vector<std::uint32_t> fill(as.first.begin(), as.first.end() - 1);
  for (std::uint32_t pi = 0; pi < as.polys.size(); ++pi)
    for (int i = 0; i < as.polys[pi].n; ++i)
      if (as.polys[pi].v[i] < nv) as.incident[fill[as.polys[pi].v[i]]++] = pi;
}

bool no_two_meet(const std::vector<StarTriangle>& tris) {
  for (const StarTriangle& t : tris)
    if (length(cross(t.p[1] - t.p[0], t.p[2] - t.p[0])) == 0) return false;
  for (std::size_t i = 0; i < tris.size(); ++i)
    for (std::size_t j = i + 1; j < tris.size(); ++j) {
      const Contact c = classify_triangle_pair(tris[i].p, tris[i].id, tris[j].p, tris[j].id);
      if (c == Contact::Cross || c == Contact::Overlap) return false;
    }
  return true;
}

// The quick test: the triangles at v, projected onto the plane of their summed normal, are
// wedges that all turn the same way and go round exactly once (then no two of them meet but
// along their shared edges). Stars it cannot vouch for (a cone over a saddle-shaped curve, say)
// get the exact pairwise triangle test instead.
bool star_ok(const Assembly& as, std::uint32_t v, std::vector<StarTriangle>& tris) {
  tris.clear();
  for (std::uint32_t k = as.first[v]; k < as.first[v + 1]; ++k) {
    const std::uint32_t pi = as.incident[k];
    const EdgePolygon& p = as.polys[pi];
    const std::uint32_t center = kFanCenter | pi;
    triangles_of(p, center, v, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      auto at = [&](std::uint32_t i) { return i == center ? p.center : as.position(i); };
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
  if (winds_along(as.nrm[v])) return true;
  Vec3 nsum;
  for (const StarTriangle& t : tris) nsum += unit(cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
  if (winds_along(unit(nsum))) return true;
  return no_two_meet(tris);
}

bool fan_ok(const Assembly& as, std::uint32_t pi, std::vector<StarTriangle>& tris) {
  const EdgePolygon& p = as.polys[pi];
  if (p.mode != EdgePolygon::Fan) return true;
  tris.clear();
  const std::uint32_t center = kFanCenter | pi;
  triangles_of(p, center, ~0u, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    tris.push_back({{c, a, b}, {p.center, as.position(a), as.position(b)}});
  });
  const int u = (p.axis + 1) % 3, w = (p.axis + 2) % 3;
  const double dir = p.dir;
  if (fan_winds_once(tris, [&](const Vec3& d) { return std::pair{d[u], dir * d[w]}; })) return true;
  return no_two_meet(tris);
}

bool vertex_ok(const Assembly& as, std::uint32_t v, std::vector<StarTriangle>& tris) {
  if (!star_ok(as, v, tris)) return false;
  for (std::uint32_t k = as.first[v]; k < as.first[v + 1]; ++k)
    if (!fan_ok(as, as.incident[k], tris)) return false;
  return true;
}

Box3 cell_box(const MeshGrid& grid, const Vec3& p) {
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
}

std::vector<Vec3> relocation_candidates(const Vec3& orig, const Vec3& centroid, const Box3& box) {
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
  return candidates;
}

// The last resort, for a vertex whose star or fans fail with every polygon a fan and its cell at
// its mass points: its neighbours are checked too, as its move changes their stars.
bool relocate(Assembly& as, std::uint32_t v, std::vector<StarTriangle>& tris) {
  star_ok(as, v, tris);
  if (tris.empty()) return false;
  Vec3 centroid;
  for (const StarTriangle& t : tris) centroid += (t.p[1] + t.p[2]) * 0.5;
  centroid = centroid / static_cast<double>(tris.size());
  const Vec3 orig = as.pos[v];
  for (const Vec3& c : relocation_candidates(orig, centroid, cell_box(as.grid, orig))) {
    as.pos[v] = c;
    bool ok = vertex_ok(as, v, tris);
    for (std::uint32_t k = as.first[v]; k < as.first[v + 1] && ok; ++k) {
      const EdgePolygon& p = as.polys[as.incident[k]];
      for (int i = 0; i < p.n && ok; ++i)
        if (p.v[i] < as.dual && p.v[i] != v) ok = vertex_ok(as, p.v[i], tris);
    }
    if (ok) return true;
  }
  as.pos[v] = orig;
  return false;
}

Repair repair_vertex(Assembly& as, std::uint32_t v, std::vector<char>& mass_points, std::vector<StarTriangle>& tris,
                     std::vector<std::uint32_t>& touched) {
  bool changed = false;
  for (std::uint32_t k = as.first[v]; k < as.first[v + 1]; ++k) {
    EdgePolygon& p = as.polys[as.incident[k]];
    if (p.mode != EdgePolygon::Fan) {
      p.mode = EdgePolygon::Fan;
      touched.push_back(as.incident[k]);
      changed = true;
    }
  }
  if (changed) return Repair::Fans;
  const std::uint32_t cell_first = v - (as.piece[v] & 15u), count = as.piece[v] >> 4;
  // (Cells with several vertices have them at their mass points already.)
  if (mass_points[cell_first] || count > 1) {
    if (!relocate(as, v, tris)) return Repair::Stuck;
    for (std::uint32_t k = as.first[v]; k < as.first[v + 1]; ++k) touched.push_back(as.incident[k]);
    return Repair::Relocated;
  }
  mass_points[cell_first] = 1;
  for (std::uint32_t u = cell_first; u < cell_first + count; ++u) {
    as.pos[u] = as.mass[u];
    for (std::uint32_t k = as.first[u]; k < as.first[u + 1]; ++k) touched.push_back(as.incident[k]);
  }
  return Repair::MassPoints;
}

std::vector<std::uint32_t> repair_vertices(Assembly& as, ThreadPool& pool) {
  const std::uint32_t nv = as.dual;
  std::vector<std::uint32_t> dirty(nv);
  for (std::uint32_t v = 0; v < nv; ++v) dirty[v] = v;
  std::vector<StarTriangle> scratch;
  std::vector<std::uint32_t> stuck, touched;
  std::vector<char> mass_points(nv, 0), bad(nv, 0), mark(nv, 0);
  for (int round = 0; round < 8 && !dirty.empty(); ++round) {
    pool.parallel_for_ranges(dirty.size(), 4096, [&](int, std::size_t b, std::size_t e) {
      std::vector<StarTriangle> tris;
      for (std::size_t i = b; i < e; ++i) bad[dirty[i]] = !vertex_ok(as, dirty[i], tris);
    });
    // Repairs in vertex order (deterministic whatever the thread count).
    std::vector<std::uint32_t> next;
    for (std::uint32_t v : dirty) {
      if (!bad[v]) continue;
      bad[v] = 0;
      touched.clear();
      if (repair_vertex(as, v, mass_points, scratch, touched) == Repair::Stuck) stuck.push_back(v);
      for (std::uint32_t pi : touched) {
        const EdgePolygon& p = as.polys[pi];
        for (int i = 0; i < p.n; ++i)
          if (p.v[i] < nv && !mark[p.v[i]]) mark[p.v[i]] = 1, next.push_back(p.v[i]);
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
  return stuck;
}

TriMesh emit_mesh(Assembly&& as) {
  std::uint64_t fans = 0, tris = 0;
  for (const EdgePolygon& p : as.polys) {
    fans += p.mode == EdgePolygon::Fan;
    tris += p.mode == EdgePolygon::Fan ? p.n : 2;
  }
  const std::uint64_t vertices = std::uint64_t{as.dual} + as.face_points.size() + fans;
  FREP_ASSERT(vertices < 0xffffffffu, "too many vertices");
  TriMesh mesh;
  mesh.vertices = std::move(as.pos);
  mesh.vertices.reserve(static_cast<std::size_t>(vertices));
  mesh.vertices.insert(mesh.vertices.end(), as.face_points.begin(), as.face_points.end());
  mesh.triangles.reserve(static_cast<std::size_t>(tris));
  for (const EdgePolygon& p : as.polys) {
    std::uint32_t center = ~0u;
    if (p.mode == EdgePolygon::Fan) {
      center = static_cast<std::uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(p.center);
    }
    triangles_of(p, center, ~0u, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { mesh.add_triangle(a, b, c); });
  }
  return mesh;
}

TriMesh assemble(const std::vector<LeafRecord*>& leaves, const MeshGrid& grid, int leaf_size, ThreadPool& pool,
                 std::size_t* unresolved) {
  Assembly as(grid);
  gather_vertices(as, leaves);
  number_face_points(as, collect_polygons(as, leaves, leaf_size, pool));
  index_incident_polygons(as);
  const std::vector<std::uint32_t> stuck = repair_vertices(as, pool);
  if (unresolved) {
    std::vector<StarTriangle> tris;
    *unresolved = 0;
    for (std::uint32_t v : stuck) *unresolved += !vertex_ok(as, v, tris);
  }
  return emit_mesh(std::move(as));
}

}  // namespace frep::contour
