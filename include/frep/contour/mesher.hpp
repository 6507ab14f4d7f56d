// Expression -> triangle mesh: `mesh_expression` (one shot) beside the reusable `Mesher`.
//
// The region is a grid of cubic cells. The subdivision driver classifies boxes of cells by
// interval arithmetic (empty, full or ambiguous), simplifying the expression on the way down;
// ambiguous leaf boxes are sampled at their cell corners. Every cell edge whose ends differ in
// sign (inside: f < 0; NaN counts as outside) gets one polygon joining the dual vertices of the
// four cells around it, with one vertex per piece of surface in a cell (docs/meshing.md, step 4),
// so the mesh is closed, manifold and oriented outward by construction, whatever the field.
// Vertices: dual contouring puts them at QEF minimizers of the edge crossings (found by root
// finding) and their normals, inside their cells; the snap method starts at the voxel corners
// and moves them onto the surface along the gradient. Output does not depend on the thread count.
#pragma once

#include <memory>

#include "frep/contour/mesh_options.hpp"
#include "frep/eval/tape.hpp"
#include "frep/expr/expr.hpp"
#include "frep/mesh/mesh.hpp"

namespace frep {

// Reusable: keeps its threads and per-thread scratch between meshes.
class Mesher {
 public:
  // Throws InputError for options out of range (resolution, cell size, bounds, tiles).
  explicit Mesher(MeshOptions options = {});
  ~Mesher();
  Mesher(const Mesher&) = delete;
  Mesher& operator=(const Mesher&) = delete;

  // Meshes the expression. Throws InputError for an unbounded field without bounds, and for a
  // grid finer than f32 coordinates can resolve; MeshCancelled if cancelled. An expression that
  // is nowhere negative gives an empty mesh.
  TriMesh mesh(const Tape& tape);
  // About the last mesh() call.
  const MeshStats& stats() const;
  const MeshOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

TriMesh mesh_expression(const Tape& tape, const MeshOptions& options = {}, MeshStats* stats = nullptr);
TriMesh mesh_expression(Expr e, const MeshOptions& options = {}, MeshStats* stats = nullptr);

}  // namespace frep
