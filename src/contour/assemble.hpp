// The mesher's last phase: one polygon per crossing edge, joining the dual vertices of the four
// cells around it (from up to four leaves), oriented outward and triangulated.
#pragma once

#include <vector>

#include "contour/leaf.hpp"
#include "contour/mesh_grid.hpp"
#include "frep/mesh/mesh.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep::contour {

// Key of the leaf whose box starts at `lo` (leaves are aligned to multiples of leaf_size).
std::uint64_t leaf_key(const std::array<int, 3>& lo, int leaf_size);

// `leaves` sorted by key. The output's vertex and triangle order depends only on the leaves.
// `unresolved` receives the number of dual vertices whose triangles still fold or cross after
// every repair (see assemble.cpp).
TriMesh assemble(const std::vector<LeafRecord*>& leaves, const MeshGrid& grid, int leaf_size, ThreadPool& pool,
                 std::size_t* unresolved = nullptr);

}  // namespace frep::contour
