// Two meshes against each other: whether their surfaces meet (and which triangles cross or
// touch), whether one lies inside the other, and the exact distance between the surfaces with the
// closest pair of points. This is the clearance of two meshed parts as a mesh query: for signed
// distances A and B of two apart solids, the minimum over space of A + B is this distance.
//
// Yes/no answers are exact for the placed double coordinates: triangle pairs are classified with
// orientation predicates only (frep/mesh/tri_tri.hpp), and nesting is the sign of a surface point
// in the other mesh's field (pseudonormal or winding number, MeshField). Distances are
// double-precision closest points between triangles (the segment-segment and vertex-face cases),
// found by a dual traversal of the two hierarchies that discards node pairs farther apart than the
// best pair yet.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "frep/math/affine.hpp"
#include "frep/math/vec.hpp"
#include "frep/mesh/mesh_field.hpp"

namespace frep {

// A mesh placed in the frame the two are compared in.
struct PlacedMesh {
  const MeshField* field = nullptr;  // the mesh (welded and checked) and its signed distance
  Affine3 place;                     // from the mesh's coordinates to the common frame

  PlacedMesh() = default;
  PlacedMesh(const MeshField& f, const Affine3& a = {}) : field(&f), place(a) {}
  // The placement of a mesh whose field is evaluated at map(p), as a moved mesh leaf is
  // (as_mesh_oracle's map): the inverse of `map`. Throws InputError if `map` is not finite or not
  // invertible.
  static PlacedMesh moved_field(const MeshField& f, const Affine3& map);
};

struct MeshPairOptions {
  int threads = 0;               // worker threads (0: all cores); the result does not depend on it
  std::size_t max_examples = 8;  // contacts listed in MeshPairResult::examples
  bool distance = true;          // find the distance and closest points when the surfaces do not meet
};

// How two triangles meet (tri_tri.hpp's Contact classes, for two different meshes).
enum class PairContact : std::uint8_t {
  Cross,    // interiors cross: the surfaces pass through each other there
  Overlap,  // coplanar, interiors overlap (faces lying on each other)
  Touch,    // the closed triangles meet, their interiors do not
};

struct MeshPairContactExample {
  std::uint32_t a = 0, b = 0;  // triangle indices (the meshes' own, as read)
  PairContact kind = PairContact::Cross;
  Vec3 point;  // a point both triangles reach (common frame; computed in double precision)
};

struct MeshPairResult {
  // --- Where the surfaces meet: counts of triangle pairs, exact.
  std::size_t crossing = 0;
  std::size_t overlapping = 0;
  std::size_t touching = 0;
  // The first few contacts: crossing pairs first, then overlapping, then touching, each kind in
  // increasing (a, b).
  std::vector<MeshPairContactExample> examples;

  // --- Nesting, decided only when the surfaces do not meet (then each shell, an edge-connected
  // piece of a surface, is wholly inside the other solid or wholly outside it).
  std::size_t a_shells = 0, b_shells = 0;                    // shells of each surface
  std::size_t a_shells_inside_b = 0, b_shells_inside_a = 0;  // those inside the other solid

  // --- The distance between the two surfaces: 0 when they meet; otherwise the smallest distance
  // between a point of A's surface and one of B's (NaN if options.distance is off), attained at
  // point_a (on triangle_a of A) and point_b (on triangle_b of B), in the common frame. Ties go
  // to the smallest (triangle_a, triangle_b).
  double distance = 0;
  Vec3 point_a, point_b;
  std::uint32_t triangle_a = 0, triangle_b = 0;

  double seconds = 0;  // time taken

  bool surfaces_meet() const { return crossing + overlapping + touching > 0; }
  // The solids share volume: their surfaces cross, or one has a shell inside the other. (Surfaces
  // that only touch may also enclose shared volume in degenerate cases, such as coincident faces
  // on the same side: surfaces_meet() without crossing leaves that open.)
  bool interfere() const { return crossing > 0 || a_shells_inside_b > 0 || b_shells_inside_a > 0; }
  // Apart: neither surfaces meeting nor nesting; `distance` is then the gap.
  bool apart() const { return !surfaces_meet() && a_shells_inside_b == 0 && b_shells_inside_a == 0; }
  // One solid inside the other: every shell of A inside B (or of B inside A), surfaces apart.
  bool a_inside_b() const { return !surfaces_meet() && a_shells > 0 && a_shells_inside_b == a_shells; }
  bool b_inside_a() const { return !surfaces_meet() && b_shells > 0 && b_shells_inside_a == b_shells; }
};

// Compares the two placed meshes. Works on the placed double coordinates (scaled by one power of
// two, which changes no predicate and no distance beyond its exponent).
MeshPairResult compare_meshes(const PlacedMesh& a, const PlacedMesh& b, const MeshPairOptions& options = {});

// The closest points of two triangles p and q (double precision): the smallest of the nine
// edge-edge and six vertex-face distances, which is the distance when the triangles do not
// intersect. Returns the squared distance; `on_p` and `on_q` receive the points.
double triangle_distance2(const Vec3 p[3], const Vec3 q[3], Vec3& on_p, Vec3& on_q);

}  // namespace frep
