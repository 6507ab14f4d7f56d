// The surface inside one grid cell, as the dual contourers see it: which crossings (edges whose
// corners differ in sign) belong together, and how many dual vertices the cell gets.
//
// Per cell, the crossings are joined on each face by segments (two crossings on a face: one
// segment; four, a face ambiguity: two segments, chosen by a per-face decision that both cells
// sharing the face compute from the same four corner values). The segments form cycles, one per
// piece of surface in the cell (the marching cubes polygons); the dual mesh has one vertex per
// cycle, and one polygon per crossing joining the vertices of the four cells around its edge.
// That dual mesh is manifold except where a cycle meets one face in two segments and the cycle
// across that face does too: the two vertices would then be joined by two edges. A cycle that
// meets a face twice is therefore split by a chord between two of its crossings into pieces that
// meet every face at most once; each piece is a dual vertex, and the two crossings at the chord's
// ends get polygons with both pieces in them. With that, every edge of the dual mesh has exactly
// two polygons and every vertex one fan (tested over all 256 sign patterns and every decision).
//
// Numbering: corner c = x + 2y + 4z (bits). Edge e = 4 * axis + u + 2 * v, where (u, v) are the
// edge's coordinates along the two other axes in increasing order. Face f = 2 * axis + side.
//
// Private to the mesher (not installed).
#pragma once

#include <array>
#include <cstdint>

namespace frep {

inline constexpr int kCellCorners = 8, kCellEdges = 12, kCellFaces = 6;

namespace detail {
// The two axes other than `a`, in increasing order.
constexpr std::array<int, 2> other_axes(int a) { return a == 0 ? std::array{1, 2} : (a == 1 ? std::array{0, 2} : std::array{0, 1}); }
struct EdgeTables {
  std::uint8_t corner[kCellEdges][2] = {};
  std::uint8_t face[kCellEdges][2] = {};
  std::uint8_t edge[3][kCellCorners] = {};
  std::uint8_t ambiguous[256] = {};
};
constexpr EdgeTables make_edge_tables() {
  EdgeTables t;
  for (int e = 0; e < kCellEdges; ++e) {
    const int a = e / 4;
    const auto o = other_axes(a);
    for (int end = 0; end < 2; ++end) t.corner[e][end] = static_cast<std::uint8_t>((end << a) | ((e & 1) << o[0]) | (((e >> 1) & 1) << o[1]));
    for (int k = 0; k < 2; ++k) t.face[e][k] = static_cast<std::uint8_t>(2 * o[k] + ((e >> k) & 1));
  }
  for (int a = 0; a < 3; ++a) {
    const auto o = other_axes(a);
    for (int c = 0; c < kCellCorners; ++c) t.edge[a][c] = static_cast<std::uint8_t>(4 * a + ((c >> o[0]) & 1) + 2 * ((c >> o[1]) & 1));
  }
  for (int config = 0; config < 256; ++config) {
    for (int f = 0; f < kCellFaces; ++f) {
      const int a = f / 2, side = f % 2;
      const auto o = other_axes(a);
      auto in = [&](int u, int v) { return (config >> ((side << a) | (u << o[0]) | (v << o[1]))) & 1; };
      if (in(0, 0) == in(1, 1) && in(1, 0) == in(0, 1) && in(0, 0) != in(1, 0)) t.ambiguous[config] |= static_cast<std::uint8_t>(1u << f);
    }
  }
  return t;
}
inline constexpr EdgeTables kEdgeTables = make_edge_tables();
}  // namespace detail
// At most this many dual vertices in one cell (pieces of surface, after splitting).
inline constexpr int kMaxCellVertices = 8;
inline constexpr std::uint8_t kNoCellVertex = 0xff;

// Corner at the low (end 0) or high (end 1) end of edge e.
constexpr int cell_edge_corner(int e, int end) { return detail::kEdgeTables.corner[e][end]; }
// The two faces that contain edge e (k = 0: perpendicular to the first other axis, 1: the second).
constexpr int cell_edge_face(int e, int k) { return detail::kEdgeTables.face[e][k]; }
// Edge along `axis` whose low corner is `corner` (bit `axis` of the corner is ignored).
constexpr int cell_edge(int axis, int corner) { return detail::kEdgeTables.edge[axis][corner]; }

// Faces whose four corners alternate in sign (inside on one diagonal, outside on the other).
constexpr std::uint8_t ambiguous_faces(std::uint8_t config) { return detail::kEdgeTables.ambiguous[config]; }

struct CellTopology {
  std::uint8_t vertices = 0;                      // dual vertices of the cell
  std::uint16_t edges[kMaxCellVertices] = {};     // per vertex: bit mask of the crossing edges it uses
  // Per crossing edge and per face containing it (k as in cell_edge_face): the vertex whose
  // piece of surface has the segment at this crossing on that face; kNoCellVertex if the edge
  // has no crossing.
  std::uint8_t vertex_at[kCellEdges][2];
  // Per crossing edge and face containing it: the crossing at the other end of its segment on
  // that face (a local edge), or -1 without a crossing.
  std::int8_t partner[kCellEdges][2];
};

// The topology for a sign pattern (bit c set: corner c is inside) and face decisions (bit f
// set: on ambiguous face f the inside corners are joined across the face, i.e. the segments cut
// off the outside corners; bits of faces that are not ambiguous are ignored). Precomputed.
const CellTopology* cell_topology_table();  // [config * 64 + decisions], decisions masked
inline const CellTopology& cell_topology(std::uint8_t config, std::uint8_t decisions) {
  static const CellTopology* const table = cell_topology_table();
  return table[static_cast<std::size_t>(config) * 64 + (decisions & ambiguous_faces(config))];
}

}  // namespace frep
