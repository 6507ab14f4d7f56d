// What frep can represent of a mesh's coordinates: the one rule that `frep convert`
// (convert_mesh) and mesh fields (MeshField, so also mesh leaves of expressions and every command
// that reads a mesh as its distance) apply before anything else.
//
// frep takes points and writes distances as 32-bit floats, and converted expressions compute in
// them (relative to the part and in units of a power of two, docs/convert.md), so:
//
// - Range: a coordinate of a vertex that a triangle uses must round to a finite float,
//   |c| < 2^128 - 2^103 (just above FLT_MAX = 3.4028235e38). Beyond, no float point can come
//   near that vertex.
// - Precision: float arithmetic resolves about 2^-20 of the part's size (the width by which the
//   converter already widens its prism tests for rounding). A mesh whose typical triangle is
//   smaller than that, i.e. the median over its triangles of the shortest edge (triangles with a
//   zero edge left out) is below 2^-20 of the diagonal of its box, would lose its shape:
//   typically a stray vertex far away (a tetrahedron with one corner at 1e30 converts to an
//   expression that reads 0 where its distance is 1, and even the double-precision distance
//   structure, whose per-triangle arithmetic mixes 1e30 with 1, is off there). Ordinary parts and
//   scans are 1e2 to 1e5 times above that limit (every shared test mesh: above 4e-4).
//
// Both refusals are InputErrors naming the mesh, the vertex (its index in the file, a triangle
// that uses it with its line, and its coordinates).
#pragma once

#include <cstdint>

#include "frep/mesh/mesh.hpp"

namespace frep {

// The largest magnitude that rounds to a finite float (exclusive): 2^128 - 2^103.
inline constexpr double kFloatRangeLimit = 0x1.ffffffp127;
// The precision rule's ratio: median shortest triangle edge / box diagonal must be >= this.
inline constexpr double kFloatSpanRatio = 0x1p-20;

struct CoordinateSpan {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  double diagonal = 0;              // of the box of the used vertices
  double median_shortest_edge = 0;  // over triangles whose shortest edge is > 0 (0 if there is none)
  double largest_coordinate = 0;    // largest |coordinate| of a used vertex
  // The used vertex farthest (largest coordinate difference) from the used vertices' median
  // point, and a triangle using it: the likely stray. kNone for a mesh without triangles.
  std::uint32_t far_vertex = kNone, far_triangle = kNone;
  // The first used vertex (in triangle order) with a coordinate beyond float range, and its
  // triangle; kNone if there is none.
  std::uint32_t out_of_range_vertex = kNone, out_of_range_triangle = kNone;
};

// The measurements the rule is made of (one pass over the triangles, plus a median).
CoordinateSpan measure_coordinate_span(const TriMesh& mesh);

// Throws InputError (named after mesh.name) unless the mesh satisfies the rule.
void check_coordinate_range(const TriMesh& mesh);

}  // namespace frep
