// The arrangement of a mesh's triangles where they cross, touch or overlap: each such triangle is
// cut, in exact arithmetic, along everything that meets it, so that the pieces of all triangles
// meet only in whole shared edges and vertices. Coplanar triangles that overlap are cut together
// in one triangulation of their plane, so that pieces covered several times are one piece with a
// multiplicity. Used by repair (repair.hpp); CGAL's exact kernel is confined to arrangement.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "frep/mesh/bvh.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/topology.hpp"

namespace frep::arrangement {

struct Piece {
  std::array<std::uint32_t, 3> v;  // vertices (Arrangement::vertices), counter-clockwise about the normal below
  int multiplicity;                // input triangles covering it with this orientation minus those with the other
  std::uint32_t source;            // one input triangle it lies in
};

struct Arrangement {
  // The input's vertices, then the new ones (intersection points rounded to the nearest double).
  std::vector<Vec3> vertices;
  // The pieces of the cut triangles, and every other triangle as it was (multiplicity 1).
  std::vector<Piece> pieces;
  std::size_t cut_triangles = 0;     // input triangles replaced by their pieces
  std::size_t coplanar_groups = 0;   // groups of overlapping coplanar triangles cut together
  std::size_t new_vertices = 0;      // points made by the cuts
  std::size_t rounded_vertices = 0;  // of those, the ones not exactly representable in double
};

// `mesh` is welded, with no collapsed or zero-area triangle; `topology` and `bvh` are built over
// it. `seeds` are the triangles known to meet others badly (crossing, touching, overlapping) or to
// lie along an edge that is not shared by exactly two triangles; the cut spreads from them to
// every triangle that meets them in more than their shared vertices and edges. `poll` is called
// regularly (it may throw to stop the work). Throws InputError if CGAL reports a failure.
Arrangement arrange(const TriMesh& mesh, const MeshTopology& topology, const TriangleBvh& bvh,
                    const std::vector<std::uint32_t>& seeds, const std::function<void()>& poll);

}  // namespace frep::arrangement
