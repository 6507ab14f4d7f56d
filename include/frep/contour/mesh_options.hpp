// What the mesher is asked to do (MeshOptions) and what it reports back (MeshStats).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "frep/contour/bounds.hpp"
#include "frep/contour/snap.hpp"
#include "frep/math/vec.hpp"

namespace frep {

enum class MeshMethod {
  DualContouring,  // vertices from QEFs of edge crossings and normals: keeps flat faces and sharp edges
  Snap,            // voxel faces, corners moved onto the surface along the gradient (simple, rounded)
};

// Cells along one axis, at most. Beyond it, memory and time stop being reasonable.
inline constexpr int kMaxMeshResolution = 4096;

struct MeshProgress {
  const char* phase = "";  // "bounds", "cells", "assembly", "simplify"
  double fraction = 0;     // of this phase done, 0 to 1
};

// How far (in cells) the vertices of a flat region may lie from its plane, and those removed from a
// straight crease from its line, for MeshOptions::merge_flat: well above the f32 noise of the
// field's crossings (about 1e-5 cells on a part 128 cells across), well below anything visible.
inline constexpr double kFlatTolerance = 1e-4;

struct MeshOptions {
  MeshMethod method = MeshMethod::DualContouring;

  // Cell size: `resolution` cells across the longest side of the bounds, unless cell_size > 0
  // (then cubes of that edge). Cells are cubes; the other sides get as many as cover them.
  int resolution = 128;
  double cell_size = 0;

  // The region to mesh. Empty (the default): found by find_bounds, and the grid gets one extra
  // cell on every side, so the surface never touches its boundary. Given: the grid covers
  // exactly this box (grown to whole cells about its center); where the shape reaches the box
  // it is cut and closed with flat caps on the box.
  Box3 bounds;
  // A box known to contain every point where the expression is negative (for example the
  // bounding box of the mesh it was converted from: expressions that take their sign from the
  // nearest feature cannot be bounded by intervals far away). Used instead of the search when
  // `bounds` is empty, with the same extra cell on every side.
  Box3 known_bounds;
  BoundsSearchOptions bounds_search;  // for the search (its thread count is `threads`)

  int threads = 0;  // worker threads; 0 = all cores. The mesh is the same for any count.
  // A known bound L on |f(p) - f(q)| / |p - q| (1 for exact distances, as frep convert writes), or
  // 0 if unknown: cells then also settle as empty or full from their centre's value (much faster
  // on converted meshes, whose intervals rarely settle a sign near the surface). Also used by the
  // bounds search.
  double lipschitz = 0;

  // Dual contouring. Crossings are found on cell edges to `edge_tolerance` (a fraction of the
  // cell) by regula falsi (Illinois), bisection where values are not finite, in at most
  // `edge_iterations` evaluations. QEF directions whose eigenvalue is below `qef_threshold`
  // times the largest stay at the mass point.
  double edge_tolerance = 1e-4;
  int edge_iterations = 24;
  double qef_threshold = 0.02;

  // The snap method: Newton steps along the gradient from the voxel corners.
  SnapOptions snap;

  // Simplification of the finished mesh: edges are collapsed while every new triangle keeps
  // |f| <= max_error at samples at most half a cell apart (docs/meshing.md), in model units, or
  // in cells when max_error_in_cells. 0 (the default, here and on the command line): none; only
  // flat regions merge (merge_flat).
  double max_error = 0;
  bool max_error_in_cells = false;
  // Flat regions (a CAD part's faces, which the grid tiles with cells) are triangulated again
  // from the corners of their outlines, before any simplification: vertices inside them and on
  // straight creases between two are removed, none moved, so the surface keeps its points (to
  // kFlatTolerance cells). Cheap (no field samples), so on by default; false (with max_error 0)
  // gives the uniform mesh of the grid.
  bool merge_flat = true;

  // Advanced: subdivision box edge per level in cells, largest first, each a multiple of the
  // next; the last is the leaf, evaluated cell by cell (at most 32). Empty: leaves of 8 cells,
  // levels growing by 4 (by 2 with a Lipschitz bound).
  std::vector<int> tiles;

  // Called now and then during long runs (from worker threads, one call at a time).
  std::function<void(const MeshProgress&)> progress;
  // Set it (from any thread) to stop: mesh() then throws MeshCancelled.
  const std::atomic<bool>* cancel = nullptr;
};

struct MeshStats {
  Box3 bounds;                      // the region meshed: the grid's box
  bool bounds_found = false;        // found by the interval search
  bool bounds_known = false;        // from MeshOptions::known_bounds
  Box3 found;                       // the search's (or the known) box, before the margin cell
  int search_rounds = 0;
  std::array<int, 3> cells{0, 0, 0};  // grid cells per axis
  double cell_size = 0;
  bool capped = false;              // the shape reached the bounds and was closed with caps there
  std::size_t leaves = 0;           // subdivision leaves with surface in them
  std::size_t surface_cells = 0;    // cells with sign changes
  std::size_t vertices = 0, triangles = 0;
  // Vertices whose triangles still fold or cross after every repair: 0 unless the field is
  // badly under-sampled (features much thinner than a cell, in many places at once).
  std::size_t unresolved = 0;
  // Grid corners (inside the grid) where the field was exactly 0 on the first pass, next to
  // another along a cell edge. Such ties (faces or edges on grid lines: touching boxes, fins one
  // cell thick, axis-aligned converted meshes) have no right side, so the grid was then shifted
  // by a small fraction of a cell and the mesh made again; `shifted` says so.
  std::size_t zero_corners = 0;
  bool shifted = false;
  // Unresolved vertices of the first grid, when there were any: the mesh was then made again on
  // grids moved by 0.37 and 0.71 of a cell, and the one with the fewest kept (`unresolved`).
  std::size_t unresolved_first = 0;
  double seconds_bounds = 0, seconds_cells = 0, seconds_assembly = 0;
  // Simplification (MeshOptions::max_error > 0): the triangles before it (0 if it did not run),
  // the bound used in model units, its time, and whether its result failed validation, in which
  // case the uniform mesh was kept.
  std::size_t triangles_before_simplify = 0;
  std::size_t flat_regions = 0;  // flat regions triangulated again (MeshOptions::merge_flat)
  double max_error = 0;
  double seconds_simplify = 0;
  bool simplify_rejected = false;
};

// Sets max_error, max_error_in_cells and merge_flat from the text users give (`--max-error`):
// "flat" merges flat regions only, "0" keeps the uniform mesh, and a bound in model units
// ("0.01") or cells ("0.05c") simplifies (flat regions first). False, options untouched, for
// anything else (not a number, negative, not finite).
bool set_max_error(MeshOptions& o, std::string_view text);

class MeshCancelled : public std::runtime_error {
 public:
  MeshCancelled() : std::runtime_error("meshing cancelled") {}
};

}  // namespace frep
