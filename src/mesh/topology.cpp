// Mesh topology: edges from the vertex-to-triangle lists (no global sort), shells and fans by
// union-find with the smallest index as the root, then normals; edge shapes on request.
#include "frep/mesh/topology.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "frep/error.hpp"
#include "frep/math/predicates.hpp"

namespace frep {

double solid_angle(const Vec3& p, const Vec3& a0, const Vec3& b0, const Vec3& c0) {
  const Vec3 a = a0 - p, b = b0 - p, c = c0 - p;
  const double la = length(a), lb = length(b), lc = length(c);
  const double num = dot(a, cross(b, c));
  const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
  return 2 * std::atan2(num, den);
}

double corner_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  return std::atan2(length(cross(e1, e2)), dot(e1, e2));
}

namespace {

constexpr std::uint32_t kNone = MeshTopology::kNone;

// Union-find whose root is always the smallest member (so a parent is never larger than its child).
std::uint32_t root_of(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}
void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = root_of(parent, a), b = root_of(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}
// Points every entry at its root: parents are never larger than their children, so one pass in
// increasing order suffices. Entries equal to kNone (not members) are left alone. Afterwards a
// second increasing pass can renumber each entry from its root, which comes first and is
// renumbered before any member reads it.
void compress(std::vector<std::uint32_t>& parent) {
  for (std::uint32_t& p : parent)
    if (p != kNone) p = parent[p];
}

// Which way the two faces of a consistent manifold edge (a, b) bend: f = (f0, f1, f2) in its
// own corner order, w_f its corner off the edge, w the other face's corner off the edge.
EdgeShape bend(const Vec3 f[3], const Vec3& a, const Vec3& b, const Vec3& w_f, const Vec3& w) {
  const int side = exact::orient3d(f[0], f[1], f[2], w);
  if (side != 0) return side < 0 ? EdgeShape::Convex : EdgeShape::Concave;
  // Coplanar: compare the sides of line ab in a coordinate projection in which f is not degenerate.
  const int axes[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  for (const auto& ax : axes) {
    const int sf = exact::orient2d(a[ax[0]], a[ax[1]], b[ax[0]], b[ax[1]], w_f[ax[0]], w_f[ax[1]]);
    if (sf == 0) continue;
    const int sw = exact::orient2d(a[ax[0]], a[ax[1]], b[ax[0]], b[ax[1]], w[ax[0]], w[ax[1]]);
    if (sw == 0) return EdgeShape::Degenerate;  // w on the line ab: the other face is a sliver
    return sw != sf ? EdgeShape::Flat : EdgeShape::Folded;
  }
  return EdgeShape::Degenerate;  // f's corners are collinear
}

}  // namespace

MeshTopology::MeshTopology(const TriMesh& m) {
  m.check_consistent();
  const std::size_t nt = m.triangles.size(), nv = m.vertices.size();
  if (nt > (std::size_t(kNone) - 1) / 3)
    throw InputError(m.name, 0, std::to_string(nt) + " triangles: more than the mesh topology handles (2^32 / 3)");
  const auto& tri = m.triangles;
  auto collapsed = [&](std::size_t t) { return tri[t][0] == tri[t][1] || tri[t][1] == tri[t][2] || tri[t][0] == tri[t][2]; };

  // Vertex -> usable triangles, by counting sort (so each list is in increasing order).
  tri_edges_.assign(nt, {kNone, kNone, kNone});
  vertex_start_.assign(nv + 1, 0);
  std::size_t usable = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    if (collapsed(t)) continue;
    ++usable;
    for (std::uint32_t v : tri[t]) ++vertex_start_[v + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) {
    used_vertices_ += vertex_start_[v + 1] != 0;
    vertex_start_[v + 1] += vertex_start_[v];
  }
  vertex_faces_.resize(3 * usable);
  std::vector<std::uint32_t> corner_slot(3 * nt);  // where corner k of t sits in its vertex's list
  {
    std::vector<std::uint32_t> fill(vertex_start_.begin(), vertex_start_.end() - 1);
    for (std::uint32_t t = 0; t < nt; ++t)
      if (!collapsed(t))
        for (int k = 0; k < 3; ++k) {
          corner_slot[3 * t + k] = fill[tri[t][k]];
          vertex_faces_[fill[tri[t][k]]++] = t;
        }
  }

  // Edges, grouped at their lower vertex: each vertex gathers its "spokes" to higher vertices and
  // sorts them (a handful), so edges come out ordered by (lower, higher) and their triangles in
  // increasing order, without sorting all 3 F half-edges at once. In the same pass, two
  // union-finds: triangles joined through any edge (shells; shell_of_ serves as it), and
  // vertex-triangle slots joined through manifold edges at both ends (fans; in fan_of_).
  struct Spoke {
    std::uint32_t other, tri;
    std::uint32_t slot_lo, slot_hi;  // tri's slots in the lists of the two ends
    std::uint8_t k;                  // which edge of `tri`
    std::uint8_t forward;            // traversed from the lower to the higher vertex
    bool operator<(const Spoke& o) const { return other != o.other ? other < o.other : tri < o.tri; }
  };
  std::vector<Spoke> spokes;
  edge_vertices_.reserve(3 * usable / 2 + 16);
  edge_face_start_.reserve(3 * usable / 2 + 17);
  edge_faces_.reserve(3 * usable);
  consistent_.reserve(3 * usable / 2 + 16);
  edge_face_start_.push_back(0);
  shell_of_.assign(nt, kNone);
  for (std::uint32_t t = 0; t < nt; ++t)
    if (!collapsed(t)) shell_of_[t] = t;
  fan_of_.resize(vertex_faces_.size());
  std::iota(fan_of_.begin(), fan_of_.end(), 0u);
  for (std::uint32_t v = 0; v < nv; ++v) {
    spokes.clear();
    for (std::uint32_t s = vertex_start_[v]; s < vertex_start_[v + 1]; ++s) {
      const std::uint32_t t = vertex_faces_[s];
      const int k = tri[t][0] == v ? 0 : (tri[t][1] == v ? 1 : 2), k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      // Edge k runs v -> corner k + 1; edge k + 2 runs corner k + 2 -> v.
      if (tri[t][k1] > v) spokes.push_back({tri[t][k1], t, s, corner_slot[3 * t + k1], std::uint8_t(k), 1});
      if (tri[t][k2] > v) spokes.push_back({tri[t][k2], t, s, corner_slot[3 * t + k2], std::uint8_t(k2), 0});
    }
    std::sort(spokes.begin(), spokes.end());
    for (std::size_t i = 0, j; i < spokes.size(); i = j) {
      const auto e = static_cast<std::uint32_t>(edge_vertices_.size());
      int forward = 0;
      for (j = i; j < spokes.size() && spokes[j].other == spokes[i].other; ++j) {
        edge_faces_.push_back(spokes[j].tri);
        tri_edges_[spokes[j].tri][spokes[j].k] = e;
        forward += spokes[j].forward;
        if (j > i) unite(shell_of_, spokes[i].tri, spokes[j].tri);
      }
      edge_vertices_.push_back({v, spokes[i].other});
      edge_face_start_.push_back(static_cast<std::uint32_t>(edge_faces_.size()));
      const std::size_t count = j - i;
      if (count == 2) {
        unite(fan_of_, spokes[i].slot_lo, spokes[i + 1].slot_lo);
        unite(fan_of_, spokes[i].slot_hi, spokes[i + 1].slot_hi);
      }
      consistent_.push_back(count == 2 && forward == 1);
    }
  }

  // Shells, renumbered in order of their first triangle, and their triangle lists.
  compress(shell_of_);
  std::uint32_t shells = 0;
  for (std::uint32_t t = 0; t < nt; ++t)
    if (shell_of_[t] != kNone) shell_of_[t] = shell_of_[t] == t ? shells++ : shell_of_[shell_of_[t]];
  shell_start_.assign(shells + 1, 0);
  for (std::uint32_t t = 0; t < nt; ++t)
    if (shell_of_[t] != kNone) ++shell_start_[shell_of_[t] + 1];
  for (std::uint32_t s = 0; s < shells; ++s) shell_start_[s + 1] += shell_start_[s];
  shell_faces_.resize(usable);
  {
    std::vector<std::uint32_t> fill(shell_start_.begin(), shell_start_.end() - 1);
    for (std::uint32_t t = 0; t < nt; ++t)
      if (shell_of_[t] != kNone) shell_faces_[fill[shell_of_[t]]++] = t;
  }

  // Fans, renumbered per vertex.
  compress(fan_of_);
  fan_count_.assign(nv, 0);
  for (std::uint32_t v = 0; v < nv; ++v)
    for (std::uint32_t s = vertex_start_[v]; s < vertex_start_[v + 1]; ++s)
      fan_of_[s] = fan_of_[s] == s ? fan_count_[v]++ : fan_of_[fan_of_[s]];

  // Normals. The vertex sums run over the triangles in increasing order.
  face_normal_.resize(nt);
  vertex_normal_.assign(nv, Vec3{});
  for (std::uint32_t t = 0; t < nt; ++t) {
    const Vec3 c[3] = {m.vertices[tri[t][0]], m.vertices[tri[t][1]], m.vertices[tri[t][2]]};
    const Vec3 n = cross(c[1] - c[0], c[2] - c[0]);
    const double l = length(n);
    face_normal_[t] = l > 0 ? n / l : Vec3{};
    if (!(l > 0)) continue;  // also every collapsed triangle: its cross product is zero
    for (int k = 0; k < 3; ++k)
      vertex_normal_[tri[t][k]] += face_normal_[t] * corner_angle(c[k], c[(k + 1) % 3], c[(k + 2) % 3]);
  }
}

std::uint32_t MeshTopology::find_edge(std::uint32_t a, std::uint32_t b) const {
  if (a == b || a >= num_vertices() || b >= num_vertices()) return kNone;
  for (std::uint32_t t : vertex_faces(a))
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = tri_edges_[t][k];
      if (edge_vertices_[e] == std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)}) return e;
    }
  return kNone;
}

Vec3 MeshTopology::edge_pseudonormal(std::uint32_t e) const {
  Vec3 sum;
  for (std::uint32_t t : edge_faces(e)) sum += face_normal_[t];
  return sum;
}

std::vector<EdgeShape> edge_shapes(const TriMesh& m, const MeshTopology& topo) {
  FREP_ASSERT(topo.num_triangles() == m.triangles.size() && topo.num_vertices() == m.vertices.size(),
              "topology of another mesh");
  std::vector<EdgeShape> shape(topo.num_edges());
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
    const std::uint32_t count = topo.edge_face_count(e);
    shape[e] = count == 1 ? EdgeShape::Boundary
               : count > 2 ? EdgeShape::NonManifold
               : topo.consistent(e) ? EdgeShape::Flat  // decided below
                                    : EdgeShape::Inconsistent;
  }
  // Each consistent edge from its first face, whose corners are at hand, and the far corner of
  // its second face.
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    if (!topo.usable(t)) continue;
    const Triangle& tr = m.triangles[t];
    const Vec3 c[3] = {m.vertices[tr[0]], m.vertices[tr[1]], m.vertices[tr[2]]};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = topo.triangle_edges(t)[k];
      if (!topo.consistent(e) || topo.edge_faces(e)[0] != t) continue;
      const std::uint32_t g = topo.edge_faces(e)[1];
      const auto& ge = topo.triangle_edges(g);
      const int kg = ge[0] == e ? 0 : (ge[1] == e ? 1 : 2);
      shape[e] = bend(c, c[k], c[(k + 1) % 3], c[(k + 2) % 3], m.vertices[m.triangles[g][(kg + 2) % 3]]);
    }
  }
  return shape;
}

}  // namespace frep
