// The steps of Mesher::mesh, each callable on its own: the options check, the region, the cell
// edge, the box the field is closed at, the subdivision tiles, the leaves, one pass over a grid,
// the rerun off corners on the surface, and the reruns while vertices stay tangled.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "contour/leaf.hpp"
#include "contour/mesh_grid.hpp"
#include "frep/contour/mesh_options.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/eval/tape.hpp"
#include "frep/mesh/mesh.hpp"

namespace frep::contour {

// Throws InputError for options out of range (resolution, cell size, bounds, tiles...).
void check_options(const MeshOptions& o);

// Leaves of 8 cells, levels growing by `growth` until the top level splits `cells` into a few
// boxes.
std::vector<int> default_tiles(int cells, int growth);

// A mesh() call's progress reports (one at a time, from any thread) and its cancel flag.
class MeshControl {
 public:
  explicit MeshControl(const MeshOptions& o) : o_(o) {}
  void report(const char* phase, double fraction);
  bool cancelled() const { return o_.cancel && o_.cancel->load(std::memory_order_relaxed); }

 private:
  const MeshOptions& o_;
  std::mutex mutex_;
};

// The region to mesh and the cells of margin the grid gets around it: the given bounds (none),
// else the known bounds or the bounds search's box (one). Empty: the search found nothing inside.
struct MeshRegion {
  Box3 box;
  int margin = 0;
  bool empty = false;
  // Found or known rather than given: closed at the grid's box, not at the region.
  bool found() const { return margin > 0; }
};
// Sets the stats about the region (bounds_found or bounds_known, found, search_rounds, seconds_bounds).
MeshRegion find_region(const Tape& tape, const MeshOptions& o, MeshControl& control, MeshStats& st);

// The cell edge: the options' cell size, else the region's longest side over the resolution.
// Throws InputError if that is not a positive number.
double cell_edge(const Box3& region, const MeshOptions& o);

// Memory a mesh takes per cell with surface in it, at its peak: leaves, vertices, polygons and
// the output (measured: about 300 bytes on a cube at 512 cells across, the same at 256).
inline constexpr std::uint64_t kBytesPerSurfaceCell = 320;
// Fine grids (more than kPilotAbove cells across) are preceded by a pilot at kPilotCells across.
inline constexpr int kPilotAbove = 512, kPilotCells = 128;

// The surface cells a grid of cell edge `h` over `region` will have, estimated from a pilot mesh
// at kPilotCells across (surface scales with the square of the resolution); 0 for grids of at
// most kPilotAbove cells across, which need no pilot, and for grids past kMaxMeshResolution,
// which make_grid refuses.
std::uint64_t estimate_surface_cells(const Tape& tape, const MeshOptions& o, const MeshRegion& region, double h);
// Throws InputError (without a file name) with the estimate when the grid would need more memory
// than the machine has, before any of the fine work.
void require_mesh_memory(const Tape& tape, const MeshOptions& o, const MeshRegion& region);

// The Lipschitz bound of the field closed at a box (max(f, box)): at least 1, the box's own.
double cut_lipschitz(double lipschitz);

// The box the field is closed at: the given region, or the grid's box for a found one; as f32
// values, not beyond the grid's box (so that its boundary corners stay outside).
Box3 cut_box(const MeshGrid& grid, const Box3& region, bool found);

// The options' tiles, else default_tiles for the grid's longest axis (halving with a bound).
std::vector<int> tiles_for(const MeshOptions& o, const MeshGrid& grid, double lipschitz);

// `sub` kept if it has these tiles and bound, else replaced (one pool at a time).
Subdivider& subdivider_for(std::unique_ptr<Subdivider>& sub, const std::vector<int>& tiles, int threads, double lipschitz);

// The subdivision's leaves that have surface, per worker, keyed by leaf_key.
struct Leaves {
  std::vector<std::vector<std::unique_ptr<LeafRecord>>> per_worker;
  // Corners exactly on the surface next to another (LeafMesher::zero_corners), over all leaves.
  std::uint64_t zero_corners = 0;
  // All of them, sorted by key (what assemble takes).
  std::vector<LeafRecord*> in_key_order() const;
};
// Subdivides the grid with the closed field and processes every leaf box. Progress ("cells") is
// reported when `reporting`; throws MeshCancelled when cancelled.
Leaves build_leaves(Subdivider& sub, const Tape& closed, const MeshGrid& grid, const Box3& cut, const MeshOptions& o,
                    MeshControl& control, bool reporting);

// What one pass over a grid gives: the mesh, and the grid's corners on the surface.
struct PassResult {
  TriMesh mesh;
  std::uint64_t zero_corners = 0;
};
// A pass on the grid moved by `shift` cells; sets the stats of that grid (times add up).
using MeshPass = std::function<PassResult(double shift)>;

// The passes of one mesh() call: grids of one cell edge over the region, with leaves, assembly
// and stats. Progress comes from the first pass only (a rerun would go back to 0).
class GridPasses {
 public:
  // Throws InputError if the region has no extent.
  GridPasses(const Tape& tape, const MeshOptions& o, const MeshRegion& region, std::unique_ptr<Subdivider>& sub,
             MeshControl& control, MeshStats& st);
  PassResult run(double shift);

 private:
  const Tape& tape_;
  const MeshOptions& o_;
  const MeshRegion& region_;
  std::unique_ptr<Subdivider>& sub_;
  MeshControl& control_;
  MeshStats& st_;
  double h_, lipschitz_;
  int passes_ = 0;
};

// The first mesh: a found region's grid is moved by 1/64 of a cell (its faces are the shape's
// extremes, on corners otherwise); with corners on the surface it is moved again, and the stats
// say so (zero_corners, shifted).
TriMesh first_mesh(const MeshPass& pass, bool found, MeshStats& st);

// With unresolved vertices, meshes again on grids moved by 0.37 and 0.71 of a cell until none
// are left, and keeps the mesh with the fewest and its stats (but the time of every pass). A
// pass that throws InputError (a cell more than allowed) or bad_alloc ends the retries.
TriMesh retry_while_unresolved(TriMesh mesh, const MeshPass& pass, const std::function<bool()>& cancelled, MeshStats& st);

}  // namespace frep::contour
