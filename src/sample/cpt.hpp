// The closest point transform behind sample_grid for valid solids (private to src/sample).
#pragma once

#include <cstddef>
#include <functional>

#include "frep/sample/grid.hpp"
#include "frep/mesh/mesh_field.hpp"

namespace frep {
class ThreadPool;
}

namespace frep::sample_detail {

// Truncated grids (options.truncate = D > 0) are computed exactly within `band` of the surface:
// D, but at least the largest voxel edge (so that the band separates the inside samples from the
// outside ones), widened by a relative hair (so that samples just beyond it are surely beyond D).
double truncation_band(const GridSpec& grid, double truncate);
// True if a truncated transform scans every polyhedron up to the band without the reach walk:
// bands of at most kScanBandVoxels voxels (the largest edge), where the walk (one oracle query
// per cell of 4^3 samples, and a cell's worth of slack) costs more than it saves (armadillo at
// 256^3: 0.71 s without it against 1.21 s with it at 12 voxels, 1.62 s against 2.15 s at 32,
// 3.26 s against 3.01 s at 64). Such a transform needs no grid bounds that contain the mesh:
// features outside the grid scan into it like the others.
constexpr double kScanBandVoxels = 32;
bool truncation_scans_band(const GridSpec& grid, double truncate);

// Writes the exact signed distance (pseudonormal sign) of every sample of `grid` to
// out[grid.index(i, j, k)], clamped to +-options.truncate if that is positive. `field` must be a
// solid; the grid box must contain its box unless truncation_scans_band().
template <class T>
void closest_point_transform(const MeshField& field, const GridSpec& grid, ThreadPool& pool, T* out,
                             const MeshGridOptions& options, MeshGridStats& stats);

}  // namespace frep::sample_detail
