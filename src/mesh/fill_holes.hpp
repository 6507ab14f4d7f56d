// Hole filling for repair (repair.hpp): each boundary loop is triangulated, refined to the
// density of the surface around it and faired (CGAL's triangulate_refine_and_fair_hole).
// CGAL is confined to fill_holes.cpp.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "frep/mesh/mesh.hpp"
#include "frep/mesh/repair.hpp"

namespace frep::holes {

struct Filled {
  TriMesh mesh;                    // the input with every hole filled
  std::vector<FilledHole> holes;   // one per hole
  std::size_t unfaired = 0;        // holes triangulated and refined but whose fairing failed
};

// `mesh` is welded and consistently oriented, each edge on one or two triangles. Returns false,
// with `why` set, where it cannot fill: a non-manifold surface, a hole with more than
// `max_boundary` edges, or a hole the triangulation cannot close.
bool fill(const TriMesh& mesh, std::size_t max_boundary, Filled& out, std::string& why);

}  // namespace frep::holes
