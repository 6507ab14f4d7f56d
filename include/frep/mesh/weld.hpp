// Welding: merging vertices that share a position, so that triangles from STL (which repeats
// every corner) or from files with seam duplicates become connected.
#pragma once

#include <cstdint>
#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep {

struct WeldOptions {
  double tolerance = 0;  // 0: merge exactly equal positions only; > 0: merge vertices closer than
                         // this (transitively), to close cracks from rounded coordinates
};

inline constexpr std::uint32_t kNoVertex = 0xffffffffu;

struct WeldResult {
  TriMesh mesh;  // welded mesh: only used vertices, triangles and provenance kept in order
  std::vector<std::uint32_t> welded_of_original;  // per input vertex: welded index, or kNoVertex if unused
  std::vector<std::uint32_t> original_of_welded;  // per welded vertex: the lowest input index merged into it
  std::size_t merged = 0;  // used input vertices minus welded vertices
};

// Merges vertices; triangles keep their order and corner order (so triangle t of the result is
// triangle t of the input). Throws InputError if the tolerance is negative or not finite.
WeldResult weld(const TriMesh& mesh, const WeldOptions& options = {});

// Per vertex, used by a triangle or not: the lowest index of a vertex at exactly the same
// position (-0 and +0 are the same), itself if there is none. Linear time.
std::vector<std::uint32_t> first_at_same_position(const std::vector<Vec3>& vertices);

}  // namespace frep
