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
#pragma once

#include <cstdint>

namespace frep {

inline constexpr int kCellCorners = 8, kCellEdges = 12, kCellFaces = 6;
// At most this many dual vertices in one cell (pieces of surface, after splitting).
inline constexpr int kMaxCellVertices = 8;
inline constexpr std::uint8_t kNoCellVertex = 0xff;

// Corner at the low (end 0) or high (end 1) end of edge e.
int cell_edge_corner(int e, int end);
// The two faces that contain edge e (k = 0: perpendicular to the first other axis, 1: the second).
int cell_edge_face(int e, int k);
// Edge along `axis` whose low corner is `corner` (bit `axis` of the corner must be 0).
int cell_edge(int axis, int corner);

// Faces whose four corners alternate in sign (inside on one diagonal, outside on the other).
std::uint8_t ambiguous_faces(std::uint8_t config);

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
const CellTopology& cell_topology(std::uint8_t config, std::uint8_t decisions);

}  // namespace frep
