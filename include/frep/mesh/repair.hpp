// Repair: the closed, manifold, outward solid a broken mesh file means. The solid is the region
// the surface winds around (generalized winding number >= 1/2): the union of overlapping shells,
// the nonzero rule of slicers. Where the input bounds a volume (closed but crossing, overlapping,
// touching, duplicated or flipped shells) the repair is exact: triangles are cut where they meet,
// in exact arithmetic, and only the pieces between inside and outside are kept, so sharp edges
// and small features survive. Holes are filled by triangulations faired to the surface around.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "frep/error.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/mesh/validate.hpp"

namespace frep {

struct RepairOptions {
  double weld_tolerance = 0;    // vertices closer than this are merged first (0: weld_relative decides)
  double weld_relative = 1e-7;  // when weld_tolerance is 0: this fraction of the box diagonal (0: exact positions only)
  bool fill_holes = true;     // fill the holes left open (false: refuse a mesh with holes)
  double time_limit = 600;    // seconds before giving up with RepairStopped (0: no limit)
  int threads = 0;            // worker threads for the checks (0: all cores)
  int max_rounds = 3;         // rounds of cutting (rounding the cut points to double may cross again)
  bool quiet = true;          // false: progress lines on stderr
  // Every output coordinate a float, for formats that store floats (STL): the input is rounded to
  // float first and every point the repair makes too, and the checks run on those coordinates.
  bool float_coordinates = false;
  // make_solid only (frep/convert/make_solid.hpp): cells across the approximation made where no
  // exact repair is found (0: refuse instead).
  int remesh_resolution = 256;
};

// What repair_mesh throws when it runs out of time (RepairOptions::time_limit).
class RepairStopped : public InputError {
 public:
  using InputError::InputError;
};

// A hole filled: where, how big.
struct FilledHole {
  std::size_t boundary_edges = 0;  // edges around it
  double area = 0;                 // of the triangles that fill it
  Vec3 at;                         // a point of its boundary
};

// What the repair did, with counts and places.
struct RepairReport {
  std::string file;
  std::size_t triangles_in = 0, triangles_out = 0;
  ValidationReport before;          // frep check of the input
  ValidationReport after;           // frep check of the output
  double weld_tolerance = 0;           // the distance within which vertices were merged
  std::size_t vertices_merged = 0;     // vertices merged into others by that weld (cracks closed)
  std::size_t degenerate_removed = 0;  // collapsed and zero-area triangles (they bound nothing)
  std::size_t triangles_turned = 0;    // turned to agree with the rest of their sheet
  std::size_t shells_turned = 0;       // closed shells turned outward (they faced inward and are no cavity)
  std::size_t crossing_pairs = 0;      // pairs cut where their interiors cross
  std::size_t overlapping_pairs = 0;   // coplanar pairs cut where they overlap
  std::size_t touching_pairs = 0;      // pairs cut where their boundaries meet
  std::size_t cut_triangles = 0;       // input triangles replaced by their pieces
  std::size_t new_vertices = 0;        // points made by the cuts
  std::size_t patches = 0;             // regions of the surface between cuts and non-manifold edges
  std::size_t patches_removed = 0;     // of those, not between inside and outside
  double area_removed = 0;             // their area
  std::size_t patches_flipped = 0;     // kept, but turned to face outward
  std::size_t vertices_separated = 0;  // where bodies touch (an edge, a corner): split, copies moved apart
  std::vector<Vec3> removed_at;        // a point of each of the first removed patches (up to 10)
  std::vector<FilledHole> holes;       // holes filled
  double volume_before = 0;            // signed volume of the input (overlaps count twice)
  double volume_after = 0;             // volume of the solid
  int rounds = 0;                      // rounds of cutting run
  bool changed = false;                // the output differs from the input (welded)
  bool exact = true;                   // no hole filled, not remeshed: the output bounds exactly the input's solid
  int remeshed = 0;                    // > 0: remeshed at this many cells across (make_solid's approximation)
  std::vector<std::string> notes;      // what the user should know, one sentence each
};

struct RepairResult {
  TriMesh mesh;  // the solid (welded; no provenance)
  RepairReport report;
};

// Repairs `mesh`. The result passes validate_mesh (report.after.is_solid()); a mesh that cannot be
// made into one (no triangles, no enclosed volume, holes with fill_holes off, a failure of the
// exact arithmetic, the time limit) gives an InputError naming the file and saying why.
RepairResult repair_mesh(const TriMesh& mesh, const RepairOptions& options = {});

// One line: what was done ("cut 334 triangles, removed 3 patches, ...; exact").
std::string repair_summary(const RepairReport& r);

// The report as text (what frep repair prints) and as JSON (frep repair --json).
std::string format_repair_report(const RepairReport& r);
std::string repair_report_json(const RepairReport& r);

}  // namespace frep
