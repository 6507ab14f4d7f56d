// Mesh topology: the connectivity of a welded triangle mesh (edges, edge-to-face and
// vertex-to-face adjacency, vertex fans, shells) and the normals built on it (unit face normals,
// angle-weighted pseudonormals), with the solid angle. One definition shared by validation, the
// distance oracle and the mesh-to-expression converter.
//
// Everything is built once, in flat arrays (CSR for the variable-length lists): about 125 bytes
// per triangle. Collapsed triangles (a vertex index repeated) take no part in any of it; they
// keep their index, with no edges and no shell.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep {

// Signed solid angle of triangle abc seen from p (Van Oosterom and Strackee), positive when p is
// on the side opposite to the right-hand normal: summed over a closed outward surface it is 4 pi
// inside and 0 outside (the generalized winding number times 4 pi).
double solid_angle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Interior angle of triangle abc at corner a, in [0, pi] (0 if an edge at a has zero length):
// the weight of the face in a's angle-weighted pseudonormal.
double corner_angle(const Vec3& a, const Vec3& b, const Vec3& c);

// How the faces of an edge meet (edge_shapes() below). Decided exactly (orient3d / orient2d on
// the coordinates given), so flat regions and creases are told apart without a tolerance.
enum class EdgeShape : std::uint8_t {
  Boundary,      // one face
  NonManifold,   // three or more faces
  Inconsistent,  // two faces traversing the edge in the same direction
  Degenerate,    // two consistent faces, one of them with collinear corners (it spans no plane)
  Flat,          // two consistent faces in one plane, on opposite sides of the edge: the plane continues
  Folded,        // two consistent faces in one plane, on the same side: folded flat onto each other
  Convex,        // two consistent faces at an angle: each lies behind the other's plane
  Concave,       // two consistent faces at an angle: each lies in front of the other's plane
};

class MeshTopology {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  MeshTopology() = default;
  // Builds from a mesh whose coincident vertices share one index (see weld.hpp); it works on the
  // indices, so unwelded copies of a vertex are different vertices here. Throws InputError for
  // an index out of range or more than 2^32 / 3 triangles.
  explicit MeshTopology(const TriMesh& welded);

  std::size_t num_vertices() const { return vertex_start_.empty() ? 0 : vertex_start_.size() - 1; }
  std::size_t num_triangles() const { return tri_edges_.size(); }
  std::size_t num_edges() const { return edge_vertices_.size(); }
  std::size_t num_shells() const { return shell_start_.empty() ? 0 : shell_start_.size() - 1; }
  // Triangles with three distinct vertices (all but the collapsed ones), and the vertices they use.
  std::size_t num_usable_triangles() const { return edge_faces_.size() / 3; }
  std::size_t num_used_vertices() const { return used_vertices_; }
  // V - E + F over the used vertices, the edges and the usable triangles: 2 per closed genus-0 shell.
  std::int64_t euler_characteristic() const {
    return std::int64_t(used_vertices_) - std::int64_t(num_edges()) + std::int64_t(num_usable_triangles());
  }
  bool usable(std::uint32_t t) const { return tri_edges_[t][0] != kNone; }

  // --- Edges: unique undirected edges, numbered in order of (lower vertex, higher vertex).
  // Edge k of triangle t joins its corners k and k + 1 (kNone for a collapsed triangle).
  const std::array<std::uint32_t, 3>& triangle_edges(std::uint32_t t) const { return tri_edges_[t]; }
  // The two endpoints, lower index first.
  const std::array<std::uint32_t, 2>& edge_vertices(std::uint32_t e) const { return edge_vertices_[e]; }
  // The triangles along the edge, in increasing order.
  std::span<const std::uint32_t> edge_faces(std::uint32_t e) const {
    return {edge_faces_.data() + edge_face_start_[e], edge_face_start_[e + 1] - edge_face_start_[e]};
  }
  std::uint32_t edge_face_count(std::uint32_t e) const { return edge_face_start_[e + 1] - edge_face_start_[e]; }
  bool manifold(std::uint32_t e) const { return edge_face_count(e) == 2; }
  // Manifold, and its two faces traverse it in opposite directions.
  bool consistent(std::uint32_t e) const { return consistent_[e] != 0; }
  // The edge joining vertices a and b (either order), or kNone.
  std::uint32_t find_edge(std::uint32_t a, std::uint32_t b) const;

  // --- Vertices.
  // The usable triangles at vertex v, in increasing order (empty for an unused vertex).
  std::span<const std::uint32_t> vertex_faces(std::uint32_t v) const {
    return {vertex_faces_.data() + vertex_start_[v], vertex_start_[v + 1] - vertex_start_[v]};
  }
  // Fans: the groups of triangles at v that are joined through manifold edges at v. A vertex of
  // a closed manifold surface has one; more than one means the surface is pinched there.
  std::uint32_t num_fans(std::uint32_t v) const { return fan_count_[v]; }
  bool pinched(std::uint32_t v) const { return fan_count_[v] > 1; }
  // Parallel to vertex_faces(v): each triangle's fan, numbered 0.. in order of the fans' first triangles.
  std::span<const std::uint32_t> vertex_fan_ids(std::uint32_t v) const {
    return {fan_of_.data() + vertex_start_[v], vertex_start_[v + 1] - vertex_start_[v]};
  }

  // --- Shells: edge-connected components (through any edge, manifold or not), numbered in order
  // of their first triangle.
  std::uint32_t shell_of(std::uint32_t t) const { return shell_of_[t]; }  // kNone if collapsed
  std::span<const std::uint32_t> shell_faces(std::uint32_t s) const {
    return {shell_faces_.data() + shell_start_[s], shell_start_[s + 1] - shell_start_[s]};
  }

  // --- Normals (Baerentzen and Aanaes, "Signed distance computation using the angle weighted
  // pseudonormal", 2005). The pseudonormals are sums, not normalized: only their direction matters.
  // Unit normal of triangle t along cross(b - a, c - a); zero where that cross product is zero.
  const Vec3& face_normal(std::uint32_t t) const { return face_normal_[t]; }
  const std::vector<Vec3>& face_normals() const { return face_normal_; }
  // Sum over the usable triangles at v of the corner angle at v times the face normal.
  const Vec3& vertex_pseudonormal(std::uint32_t v) const { return vertex_normal_[v]; }
  const std::vector<Vec3>& vertex_pseudonormals() const { return vertex_normal_; }
  // Sum of the face normals of the edge's triangles (in increasing order).
  Vec3 edge_pseudonormal(std::uint32_t e) const;

 private:
  std::vector<std::array<std::uint32_t, 3>> tri_edges_;     // per triangle
  std::vector<std::array<std::uint32_t, 2>> edge_vertices_;  // per edge
  std::vector<std::uint32_t> edge_face_start_, edge_faces_;  // CSR: edge -> triangles
  std::vector<std::uint8_t> consistent_;                     // per edge
  std::vector<std::uint32_t> vertex_start_, vertex_faces_;  // CSR: vertex -> triangles
  std::vector<std::uint32_t> fan_of_;                        // parallel to vertex_faces_
  std::vector<std::uint32_t> fan_count_;                     // per vertex
  std::vector<std::uint32_t> shell_of_;                      // per triangle
  std::vector<std::uint32_t> shell_start_, shell_faces_;    // CSR: shell -> triangles
  std::vector<Vec3> face_normal_;                            // per triangle
  std::vector<Vec3> vertex_normal_;                          // per vertex
  std::size_t used_vertices_ = 0;
};

// How the faces of each edge meet (indexed by edge id), decided exactly on the coordinates of
// `welded`, the mesh `topology` was built from. One pass over the triangles, on request: the
// converter needs it, validation and the distance oracle do not.
std::vector<EdgeShape> edge_shapes(const TriMesh& welded, const MeshTopology& topology);

}  // namespace frep
