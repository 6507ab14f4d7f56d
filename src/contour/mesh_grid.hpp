// The mesher's cell grid: cubic cells over a box, their f32 corner coordinates, and the
// expression closed off at the grid's boundary (so the mesh is closed even where the shape is cut).
#pragma once

#include <array>

#include "frep/contour/mesh_options.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/eval/tape.hpp"
#include "frep/math/vec.hpp"

namespace frep::contour {

struct MeshGrid {
  std::array<int, 3> n{0, 0, 0};  // cells per axis
  double h = 0;                   // cell edge
  SampleGrid grid;                // corner coordinates (f32), cells = true
  Box3 box;                       // [first corner, last corner] per axis (the f32 values)

  // Corner coordinate along an axis, as the evaluators see it.
  double coord(int axis, int i) const { return grid.coords[static_cast<std::size_t>(axis)][static_cast<std::size_t>(i)]; }
};

// Cells of edge h centered on `region`; `margin` extra cells on every side; corners moved by
// `shift` cells along every axis (times 1, 0.71 and 0.43: no plane or diagonal keeps its place).
// Throws InputError if an axis would need more than kMaxMeshResolution cells, or if f32 cannot
// resolve the corners.
MeshGrid make_grid(const Box3& region, double h, int margin, double shift = 0);

// max(f, d) with d the f32 distance-like function of `box` (negative inside, 0 on its faces):
// identical to f where f's surface is inside the box, >= 0 outside it. With a box inside the
// grid's box, every corner on the grid's boundary is outside, and a shape that reaches the box
// is cut there and closed with flat caps on its faces.
Tape close_at_box(const Tape& tape, const Box3& box);

}  // namespace frep::contour
