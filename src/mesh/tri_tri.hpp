// Exact classification of how two triangles of a mesh meet, for the self-intersection check.
// Only orientation predicates are used (no constructed points), so the answer is exact for the
// double coordinates given.
#pragma once

#include "frep/math/vec.hpp"

namespace frep {

enum class Contact {
  None,     // disjoint, or meeting only in the vertices/edge they share as mesh neighbours
  Touch,    // closed triangles meet but their interiors do not (vertex on face, edge on edge...)
  Cross,    // non-coplanar triangles whose interiors intersect: the surface passes through itself
  Overlap,  // coplanar triangles whose interiors overlap (includes folds across a shared edge)
};

// p and q are the corners; pi and qi the mesh vertex indices, used to recognise shared corners
// (a shared index means the same point). Both triangles must have non-zero area (callers skip
// degenerate ones). With shared corners only Cross and Overlap are reported, never Touch.
Contact classify_triangle_pair(const Vec3 p[3], const unsigned pi[3], const Vec3 q[3], const unsigned qi[3]);

}  // namespace frep
