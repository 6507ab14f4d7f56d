// The per-cell topology table: segments per face, cycles, and cycles split so that no piece
// meets a face twice (see cell_topology.hpp for why).
#include "contour/cell_topology.hpp"

#include <array>
#include <vector>

#include "frep/error.hpp"

namespace frep {
namespace {

using detail::other_axes;

bool crosses(std::uint8_t config, int e) {
  return ((config >> cell_edge_corner(e, 0)) & 1) != ((config >> cell_edge_corner(e, 1)) & 1);
}

// A cycle: crossings c[i], and the face of the segment from c[i] to c[i+1] (-1 for a chord).
struct Cycle {
  std::vector<int> edges;
  std::vector<int> faces;
};

void split(const Cycle& cy, std::vector<Cycle>& out) {
  const int k = static_cast<int>(cy.edges.size());
  for (int i = 0; i < k; ++i) {
    if (cy.faces[i] < 0) continue;
    for (int j = i + 1; j < k; ++j) {
      if (cy.faces[j] != cy.faces[i]) continue;
      // Segments i and j lie on one face: chord from c[i+1] to c[j+1]. Piece A runs from c[i+1]
      // to c[j+1] (it keeps segment j), piece B from c[j+1] round to c[i+1] (segment i).
      Cycle a, b;
      for (int t = i + 1; t <= j; ++t) {
        a.edges.push_back(cy.edges[t]);
        a.faces.push_back(cy.faces[t]);
      }
      a.edges.push_back(cy.edges[(j + 1) % k]);
      a.faces.push_back(-1);
      for (int t = j + 1; t <= i + k; ++t) {
        b.edges.push_back(cy.edges[t % k]);
        b.faces.push_back(cy.faces[t % k]);
      }
      b.edges.push_back(cy.edges[(i + 1) % k]);
      b.faces.push_back(-1);
      FREP_ASSERT(a.edges.size() >= 3 && b.edges.size() >= 3, "degenerate cycle split");
      split(a, out);
      split(b, out);
      return;
    }
  }
  out.push_back(cy);
}

CellTopology build(std::uint8_t config, std::uint8_t decisions) {
  CellTopology t;
  for (auto& row : t.vertex_at) row[0] = row[1] = kNoCellVertex;
  for (auto& row : t.partner) row[0] = row[1] = -1;
  // partner[e][k]: the crossing joined to e by the segment on face cell_edge_face(e, k).
  int partner[kCellEdges][2];
  for (auto& p : partner) p[0] = p[1] = -1;
  const std::uint8_t amb = ambiguous_faces(config);
  for (int f = 0; f < kCellFaces; ++f) {
    const int a = f / 2, side = f % 2;
    const int p = other_axes(a)[0], q = other_axes(a)[1];  // (not a structured binding: lambdas capture them)
    // The face's corners (u along p, v along q) and its edges.
    auto corner = [&](int u, int v) { return (side << a) | (u << p) | (v << q); };
    auto inside = [&](int c) { return (config >> c) & 1; };
    // Crossing edges of the face adjacent to corner (u, v): along p and along q.
    auto edge_p = [&](int v) { return cell_edge(p, corner(0, v)); };
    auto edge_q = [&](int u) { return cell_edge(q, corner(u, 0)); };
    auto join = [&](int e0, int e1) {
      auto slot = [&](int e) { return cell_edge_face(e, 0) == f ? 0 : 1; };
      FREP_ASSERT(cell_edge_face(e0, slot(e0)) == f && cell_edge_face(e1, slot(e1)) == f, "edge not on face");
      partner[e0][slot(e0)] = e1;
      partner[e1][slot(e1)] = e0;
    };
    if (amb >> f & 1) {
      // Cut off the corners of one kind: the outside ones if the inside is joined across.
      const int cut = (decisions >> f & 1) ? 0 : 1;
      for (int u = 0; u < 2; ++u)
        for (int v = 0; v < 2; ++v)
          if (inside(corner(u, v)) == cut) join(edge_p(v), edge_q(u));
    } else {
      int found[4], n = 0;
      const int es[4] = {edge_p(0), edge_p(1), edge_q(0), edge_q(1)};
      for (int e : es)
        if (crosses(config, e)) found[n++] = e;
      FREP_ASSERT(n == 0 || n == 2, "a face without ambiguity has 0 or 2 crossings");
      if (n == 2) join(found[0], found[1]);
    }
  }
  for (int e = 0; e < kCellEdges; ++e)
    for (int k = 0; k < 2; ++k) t.partner[e][k] = static_cast<std::int8_t>(partner[e][k]);
  // Trace the cycles.
  bool seen[kCellEdges] = {};
  std::vector<Cycle> pieces;
  for (int e0 = 0; e0 < kCellEdges; ++e0) {
    if (!crosses(config, e0) || seen[e0]) continue;
    Cycle cy;
    int cur = e0, k = 0;  // leave e0 through face slot 0
    do {
      FREP_ASSERT(partner[cur][k] >= 0, "open cycle");
      seen[cur] = true;
      cy.edges.push_back(cur);
      const int f = cell_edge_face(cur, k);
      cy.faces.push_back(f);
      const int next = partner[cur][k];
      k = cell_edge_face(next, 0) == f ? 1 : 0;  // leave `next` through its other face
      cur = next;
    } while (cur != e0);
    FREP_ASSERT(k == 0, "cycle closed on the wrong face");
    split(cy, pieces);
  }
  FREP_ASSERT(pieces.size() <= static_cast<std::size_t>(kMaxCellVertices), "too many pieces in a cell");
  t.vertices = static_cast<std::uint8_t>(pieces.size());
  for (std::size_t v = 0; v < pieces.size(); ++v) {
    const Cycle& cy = pieces[v];
    const int k = static_cast<int>(cy.edges.size());
    for (int i = 0; i < k; ++i) {
      t.edges[v] |= static_cast<std::uint16_t>(1u << cy.edges[i]);
      const int f = cy.faces[i];
      if (f < 0) continue;
      for (int e : {cy.edges[i], cy.edges[(i + 1) % k]}) {
        const int slot = cell_edge_face(e, 0) == f ? 0 : 1;
        FREP_ASSERT(t.vertex_at[e][slot] == kNoCellVertex, "segment end claimed twice");
        t.vertex_at[e][slot] = static_cast<std::uint8_t>(v);
      }
    }
  }
  return t;
}

struct Table {
  std::vector<CellTopology> entries;
  Table() : entries(256 * 64) {
    for (int c = 0; c < 256; ++c) {
      const std::uint8_t amb = ambiguous_faces(static_cast<std::uint8_t>(c));
      for (int d = 0; d < 64; ++d)
        if ((d & ~amb) == 0) entries[static_cast<std::size_t>(c * 64 + d)] = build(static_cast<std::uint8_t>(c), static_cast<std::uint8_t>(d));
    }
  }
};

}  // namespace

const CellTopology* cell_topology_table() {
  static const Table table;
  return table.entries.data();
}

}  // namespace frep
