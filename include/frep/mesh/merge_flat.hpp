// Merging flat regions of a closed mesh: every region of triangles that lie in one plane (within
// a tolerance) is triangulated again from the corners of its outline alone. The surface keeps its
// points (to the tolerance), so what was a solid without crossings stays one; a grid mesher's
// tiling of a CAD part's faces shrinks to about the part's own triangles.
#pragma once

#include <cstddef>

#include "frep/mesh/mesh.hpp"

namespace frep {

struct MergeFlatReport {
  std::size_t regions = 0;   // flat regions triangulated again
  std::size_t refused = 0;   // flat regions left as they were (their outline could not be triangulated)
  std::size_t removed = 0;   // vertices removed: inside flat regions, or on straight creases between two
};

// `mesh`: closed, manifold, consistently oriented, vertices shared by index (as the mesher makes).
// `tolerance`: how far (a distance) from a region's plane its vertices, and from a straight crease's
// line the vertices removed from it, may be. Vertices are removed, never moved, so sharp edges and
// corners stay where they were. Returns the merged mesh, vertices renumbered in their old order.
TriMesh merge_flat_regions(const TriMesh& mesh, double tolerance, MergeFlatReport* report = nullptr);

}  // namespace frep
