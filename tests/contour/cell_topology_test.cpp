// The per-cell topology table, checked over every sign pattern and every face decision against
// properties derived independently: crossings are the edges whose corners differ in sign; each
// crossing has exactly one vertex per face at it; a vertex's crossings touch each face at most
// once (what makes the dual mesh manifold); the number of pieces (before splitting) equals the
// number of boundary components between inside and outside regions on the cube's surface,
// counted by a flood fill over the surface that knows nothing about segments and cycles.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "contour/cell_topology.hpp"

namespace frep {
namespace {

int corner_bit(int c, int axis) { return (c >> axis) & 1; }

// Connected components of the inside and of the outside corners on the cube's surface: corners
// joined along cube edges, and across an ambiguous face's diagonal for the kind the decision
// joins (inside if the decision bit is set, outside otherwise).
int surface_regions(std::uint8_t config, std::uint8_t decisions) {
  int parent[8];
  for (int i = 0; i < 8; ++i) parent[i] = i;
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto join = [&](int a, int b) { parent[find(a)] = find(b); };
  auto inside = [&](int c) { return (config >> c) & 1; };
  for (int a = 0; a < 8; ++a)
    for (int b = a + 1; b < 8; ++b) {
      const int diff = a ^ b;
      if ((diff & (diff - 1)) == 0 && inside(a) == inside(b)) join(a, b);  // along an edge
    }
  const std::uint8_t amb = ambiguous_faces(config);
  for (int f = 0; f < 6; ++f) {
    if (!(amb >> f & 1)) continue;
    const int axis = f / 2, side = f % 2;
    std::vector<int> cs;
    for (int c = 0; c < 8; ++c)
      if (corner_bit(c, axis) == side) cs.push_back(c);
    const int joined_kind = (decisions >> f & 1) ? 1 : 0;
    for (int a : cs)
      for (int b : cs)
        if (a < b && inside(a) == joined_kind && inside(b) == joined_kind) join(a, b);
  }
  std::set<int> roots;
  for (int c = 0; c < 8; ++c) roots.insert(find(c));
  return static_cast<int>(roots.size());
}

TEST(CellTopology, EdgeNumbering) {
  for (int e = 0; e < kCellEdges; ++e) {
    const int a = e / 4, c0 = cell_edge_corner(e, 0), c1 = cell_edge_corner(e, 1);
    EXPECT_EQ(c0 ^ c1, 1 << a);
    EXPECT_EQ(corner_bit(c0, a), 0);
    EXPECT_EQ(cell_edge(a, c0), e);
    for (int k = 0; k < 2; ++k) {
      const int f = cell_edge_face(e, k), fa = f / 2, side = f % 2;
      EXPECT_NE(fa, a);
      EXPECT_EQ(corner_bit(c0, fa), side);  // both ends lie on the face
      EXPECT_EQ(corner_bit(c1, fa), side);
    }
    EXPECT_NE(cell_edge_face(e, 0) / 2, cell_edge_face(e, 1) / 2);
  }
}

TEST(CellTopology, EveryPatternAndDecision) {
  int split_cells = 0;
  for (int config = 0; config < 256; ++config) {
    const auto cfg = static_cast<std::uint8_t>(config);
    const std::uint8_t amb = ambiguous_faces(cfg);
    for (int d = 0; d < 64; ++d) {
      if (d & ~amb) continue;
      const auto dec = static_cast<std::uint8_t>(d);
      const CellTopology& t = cell_topology(cfg, dec);
      SCOPED_TRACE("config " + std::to_string(config) + " decisions " + std::to_string(d));
      // Crossings: exactly the edges whose ends differ.
      std::uint16_t crossings = 0;
      for (int e = 0; e < kCellEdges; ++e)
        if (((cfg >> cell_edge_corner(e, 0)) & 1) != ((cfg >> cell_edge_corner(e, 1)) & 1)) crossings |= 1u << e;
      std::uint16_t covered = 0;
      for (int v = 0; v < t.vertices; ++v) {
        EXPECT_NE(t.edges[v], 0);
        covered |= t.edges[v];
      }
      EXPECT_EQ(covered, crossings);
      for (int e = 0; e < kCellEdges; ++e) {
        const bool crossing = crossings >> e & 1;
        for (int k = 0; k < 2; ++k) {
          const std::uint8_t v = t.vertex_at[e][k];
          if (!crossing) {
            EXPECT_EQ(v, kNoCellVertex);
            EXPECT_EQ(t.partner[e][k], -1);
            continue;
          }
          ASSERT_LT(v, t.vertices);
          EXPECT_TRUE(t.edges[v] >> e & 1) << "vertex at a crossing it does not use";
          // The segment's other end is a crossing on the same face, pointing back, same vertex.
          const int p = t.partner[e][k], f = cell_edge_face(e, k);
          ASSERT_GE(p, 0);
          EXPECT_TRUE(crossings >> p & 1);
          const int pk = cell_edge_face(p, 0) == f ? 0 : 1;
          EXPECT_EQ(cell_edge_face(p, pk), f);
          EXPECT_EQ(t.partner[p][pk], e);
          EXPECT_EQ(t.vertex_at[p][pk], v);
        }
      }
      // No vertex has two segments on one face: per face, a vertex owns at most 2 (edge, face)
      // slots there (the two ends of its one segment).
      for (int v = 0; v < t.vertices; ++v)
        for (int f = 0; f < 6; ++f) {
          int slots = 0;
          for (int e = 0; e < kCellEdges; ++e)
            for (int k = 0; k < 2; ++k)
              if (cell_edge_face(e, k) == f && t.vertex_at[e][k] == v) ++slots;
          EXPECT_TRUE(slots == 0 || slots == 2) << "vertex " << v << " face " << f << " slots " << slots;
        }
      // Pieces: boundary cycles between inside and outside regions on the sphere = regions - 1.
      const int cycles = crossings ? surface_regions(cfg, dec) - 1 : 0;
      EXPECT_GE(t.vertices, cycles);
      if (t.vertices > cycles) ++split_cells;
      if (config == 0 || config == 255) {
        EXPECT_EQ(t.vertices, 0);
      }
    }
  }
  // Some patterns do need splitting (a piece meeting a face twice), e.g. the one in the header.
  EXPECT_GT(split_cells, 0);
}

// The example from the header: corners 0, 3, 4, 5, 7 inside, outside joined across the bottom
// face: one cycle meets the bottom face twice and must be split into two vertices.
TEST(CellTopology, CycleMeetingAFaceTwiceIsSplit) {
  const std::uint8_t config = (1 << 0) | (1 << 3) | (1 << 4) | (1 << 5) | (1 << 7);
  EXPECT_EQ(ambiguous_faces(config) & (1 << 4), 1 << 4);  // face -z is ambiguous
  EXPECT_EQ(surface_regions(config, 0), 2);               // one cycle
  EXPECT_EQ(cell_topology(config, 0).vertices, 2);        // split in two
}

}  // namespace
}  // namespace frep
