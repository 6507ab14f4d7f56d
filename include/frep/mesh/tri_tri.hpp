// Exact classification of how two triangles of a mesh meet: the self-intersection check, repair,
// two meshes against each other (mesh_pair.hpp) and the mesher's fold test all ask it. Only
// orientation predicates are used (no constructed points), so the answer is exact for the
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

// What a caller may know about corners lying in the other triangle's plane (validation: a corner
// of a triangle of the other's flat region). Asked only where the predicates' float filter cannot
// decide, which on CAD parts is mostly such corners (an exact zero the filter cannot certify):
// on_plane(context, which, k) is true if corner k of p (which = 0) lies in q's plane, or corner k
// of q (which = 1) in p's. It must only say so when it is exactly true.
struct PlaneHint {
  bool (*on_plane)(const void* context, int which, int corner) = nullptr;
  const void* context = nullptr;
};

// p and q are the corners; pi and qi the mesh vertex indices, used to recognise shared corners
// (a shared index means the same point). Both triangles must have non-zero area (callers skip
// degenerate ones). With shared corners only Cross and Overlap are reported, never Touch.
// `coplanar` tells that the caller knows, exactly, that both lie in one plane (triangles of one
// flat region of the mesh): their orientation signs against each other's plane, all 0, are then
// not computed. `hint`, if given, may save exact evaluations the same way. The answer is the same.
Contact classify_triangle_pair(const Vec3 p[3], const unsigned pi[3], const Vec3 q[3], const unsigned qi[3],
                               bool coplanar = false, const PlaneHint* hint = nullptr);

}  // namespace frep
