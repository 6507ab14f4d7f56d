// Error-bounded simplification of the mesher's output: edge collapses ordered by quadric error,
// each accepted only if the mesh stays closed, manifold, unfolded and free of crossings, and the
// new triangles stay within the error bound of the field's zero set (|f| checked at samples).
#pragma once

#include <cstddef>
#include <functional>

#include "frep/eval/tape.hpp"
#include "frep/mesh/mesh.hpp"

namespace frep::contour {

struct SimplifyOptions {
  double max_error = 0;  // bound on |f| over the output triangles, in model units (> 0)
  double cell_size = 0;  // the grid's cell: sets the sample spacing, the spatial hash and the regions
  int threads = 0;       // worker threads; 0 = all cores. The result is the same for any count.
  // Called now and then with the fraction done (from worker threads, one call at a time).
  std::function<void(double)> progress;
  // Checked between regions: returns true to stop (simplify_mesh then throws MeshCancelled).
  std::function<bool()> cancelled;
};

struct SimplifyReport {
  std::size_t collapses = 0;  // edges collapsed
  std::size_t rejected = 0;   // candidate collapses refused by one of the checks
};

// Collapses edges of `mesh` (a closed, manifold, outward mesh without crossings, as the mesher
// makes) while every check holds; returns the simplified mesh (vertices renumbered, in their old
// order). Half-edge collapses only: every output vertex is an input vertex at its exact position,
// so the sharp edges and corners the QEF placed stay where they were. Regions of the mesh are
// simplified in parallel first, then the seams between them; deterministic for any thread count.
TriMesh simplify_mesh(const TriMesh& mesh, const Tape& tape, const SimplifyOptions& options, SimplifyReport* report);

}  // namespace frep::contour
