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

// Writes the exact signed distance (pseudonormal sign) of every sample of `grid` to
// out[grid.index(i, j, k)]. `field` must be a solid; the grid box must contain its box.
template <class T>
void closest_point_transform(const MeshField& field, const GridSpec& grid, ThreadPool& pool, T* out,
                             const MeshGridOptions& options, MeshGridStats& stats);

}  // namespace frep::sample_detail
