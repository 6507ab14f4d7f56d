// The steps of `assemble` (assemble.cpp explains the method), each callable on its own: the
// polygons around crossing edges, their face points, their triangles, the checks of a vertex's
// star and of a fan, the repairs, and the output. The state they share is an `Assembly`.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "contour/leaf.hpp"
#include "contour/mesh_grid.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep::contour {

// The polygon of one crossing edge, outward: 4 to 8 dual vertices, and the face points between
// some of them (12 entries at most).
struct EdgePolygon {
  enum Mode : std::uint8_t { SplitA, SplitB, Fan };  // A: diagonal 0-2, B: diagonal 1-3 (quads)
  std::uint32_t v[12];
  std::uint8_t n = 0;
  Mode mode = Fan;
  std::uint8_t axis = 0;  // the edge's axis
  std::int8_t dir = 1;    // outward along +axis (1) or -axis (-1)
  Vec3 center;            // a point of the edge near its crossing: the fan's center
};

// Marks, in a leaf's polygons, the index of one of its face point keys (until numbered).
inline constexpr std::uint32_t kRouted = 0x80000000u;
// A fan center's id in the checks: this bit with its polygon's index, above every vertex id.
inline constexpr std::uint32_t kFanCenter = 0x80000000u;

// A face point: the point between the midpoints of two grid edges (edge_id), lower id first.
struct FacePointKey {
  std::uint64_t e0, e1;
  bool operator<(const FacePointKey& o) const { return e0 != o.e0 ? e0 < o.e0 : e1 < o.e1; }
  bool operator==(const FacePointKey& o) const { return e0 == o.e0 && e1 == o.e1; }
};

// A leaf's face point keys, and its polygons (a range) whose kRouted entries index them.
struct LeafFacePoints {
  std::size_t first_polygon = 0, end_polygon = 0;
  std::vector<FacePointKey> keys;
};

// What the steps share. Ids below `dual` are dual vertices, then come the face points.
struct Assembly {
  explicit Assembly(const MeshGrid& g) : grid(g) {}
  const MeshGrid& grid;
  std::uint32_t dual = 0;
  std::vector<Vec3> pos, mass, nrm;      // per dual vertex: position, fallback, normal (or zero)
  std::vector<std::uint8_t> piece;       // as LeafRecord::piece
  std::vector<EdgePolygon> polys;
  std::vector<Vec3> face_points;
  std::vector<std::uint32_t> first, incident;  // dual vertex -> its polygons (CSR)

  const Vec3& position(std::uint32_t id) const { return id < dual ? pos[id] : face_points[id - dual]; }
};

// A triangle of a star or a fan, first corner at the vertex (or fan center) it is about.
struct StarTriangle {
  unsigned id[3];
  Vec3 p[3];
};

// Global id of a grid edge: its low corner and axis.
std::uint64_t edge_id(const MeshGrid& g, const int corner[3], int axis);
Vec3 edge_midpoint(const MeshGrid& g, std::uint64_t id);

// Numbers the leaves' vertices in leaf order (setting vertex_offset) and copies them in.
// `leaves` must be sorted by key.
void gather_vertices(Assembly& as, const std::vector<LeafRecord*>& leaves);

// One polygon per crossing edge, in leaf order and within a leaf in cell and axis order; quads
// get a diagonal, the rest are fans. Face points are left as per-leaf keys (kRouted entries).
std::vector<LeafFacePoints> collect_polygons(Assembly& as, const std::vector<LeafRecord*>& leaves, int leaf_size,
                                             ThreadPool& pool);

// The better diagonal of the quad q (corner normals n, outward direction `outward`): the one that
// avoids a sliver if only one does, else that keeps both triangles facing outward if only one
// does, else the one nearer the tangent planes at its ends.
EdgePolygon::Mode choose_diagonal(const Vec3 q[4], const Vec3 n[4], const Vec3& outward);

// One vertex per distinct face point key, numbered after the dual vertices in key order, and the
// polygons' kRouted entries replaced by those numbers.
void number_face_points(Assembly& as, const std::vector<LeafFacePoints>& leaves);

// For every dual vertex, the polygons it is in (ascending).
void index_incident_polygons(Assembly& as);

// Calls emit(a, b, c) for the triangles of `p` (`center`: the index of its fan center) that
// contain `only` (all if ~0), each turning as the polygon does.
template <class F>
void triangles_of(const EdgePolygon& p, std::uint32_t center, std::uint32_t only, F&& emit) {
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (only == ~0u || a == only || b == only || c == only) emit(a, b, c);
  };
  if (p.mode == EdgePolygon::SplitA) {
    tri(p.v[0], p.v[1], p.v[2]);
    tri(p.v[0], p.v[2], p.v[3]);
  } else if (p.mode == EdgePolygon::SplitB) {
    tri(p.v[0], p.v[1], p.v[3]);
    tri(p.v[1], p.v[2], p.v[3]);
  } else {
    for (int i = 0; i < p.n; ++i) tri(p.v[i], p.v[(i + 1) % p.n], center);
  }
}

// Do the triangles about their first corner, projected to 2D by `proj`, turn the same way
// (counter-clockwise, each by less than half a turn and clearly more than none) and go round
// exactly once? The turns are counted as the triangles that cross the ray along +x from below.
// Nearly flat turns are left to the exact test (a sliver may be folded).
template <class Proj>
bool fan_winds_once(const std::vector<StarTriangle>& tris, Proj&& proj) {
  int crossings = 0;
  for (const StarTriangle& t : tris) {
    const auto [ax, ay] = proj(t.p[1] - t.p[0]);
    const auto [bx, by] = proj(t.p[2] - t.p[0]);
    if (!(ax * by - ay * bx > 1e-9 * std::sqrt((ax * ax + ay * ay) * (bx * bx + by * by)))) return false;
    crossings += ay < 0 && by >= 0;
  }
  return crossings == 1;
}

// The exact test: no triangle has zero area and no two cross or overlap.
bool no_two_meet(const std::vector<StarTriangle>& tris);

// Vertex v's star (its triangles, into `tris`) winds once about v seen along its normal or the
// triangles' mean normal, or else passes the exact test.
bool star_ok(const Assembly& as, std::uint32_t v, std::vector<StarTriangle>& tris);
// Polygon pi, if a fan, winds once about its center seen along its edge, or passes the exact test.
bool fan_ok(const Assembly& as, std::uint32_t pi, std::vector<StarTriangle>& tris);
// Vertex v's star passes and so does every fan it is in.
bool vertex_ok(const Assembly& as, std::uint32_t v, std::vector<StarTriangle>& tris);

// The cell (of the grid) that p is in, shrunk by kVertexInset on every side.
Box3 cell_box(const MeshGrid& grid, const Vec3& p);
// Positions to try for a vertex at `orig` in `box`: towards `centroid` (all the way, half,
// three quarters, a quarter), then a 5x5x5 lattice over the box nearest first; all f32 values
// inside the box.
std::vector<Vec3> relocation_candidates(const Vec3& orig, const Vec3& centroid, const Box3& box);
// Moves v to the first candidate position in its cell where v and every vertex it shares a
// polygon with pass vertex_ok; false (v left in place) if there is none.
bool relocate(Assembly& as, std::uint32_t v, std::vector<StarTriangle>& tris);

// What repair_vertex did to a failing vertex.
enum class Repair { Fans, MassPoints, Relocated, Stuck };
// The first repair that applies to failing vertex v: its split quads become fans; else (once per
// cell) its cell's vertices go back to their mass points; else it is relocated. `mass_points`
// marks the cells (by first vertex) already moved. Appends to `touched` the polygons whose
// vertices must be checked again.
Repair repair_vertex(Assembly& as, std::uint32_t v, std::vector<char>& mass_points, std::vector<StarTriangle>& tris,
                     std::vector<std::uint32_t>& touched);

// Checks every vertex, repairs those that fail and checks again next to the repairs, for at most
// 8 rounds, in vertex order (the same result for any thread count). Returns the vertices that
// may still fail (sorted, each once): those no repair helped when they failed, and those left
// after the last round. Every other vertex passes.
std::vector<std::uint32_t> repair_vertices(Assembly& as, ThreadPool& pool);

// The mesh: the dual vertices, the face points, then the fan centers in polygon order; the
// triangles in polygon order.
TriMesh emit_mesh(Assembly&& as);

}  // namespace frep::contour
