// Tetrahedralization by the separate TetGen program (AGPL: run as a child process, never linked),
// private to the converter. TetGen crashes on some inputs; every failure becomes an InputError.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "frep/mesh/mesh.hpp"

namespace frep::convert_detail {

struct Tetrahedralization {
  std::vector<Vec3> points;                        // the mesh's vertices first, then TetGen's interior points
  std::vector<std::array<std::uint32_t, 4>> tets;  // oriented: d lies on the right-hand normal side of abc
};

// Runs `tetgen -pYQ` on the welded closed mesh (its surface preserved, no points added on it)
// with a time limit, and checks that the tetrahedra's boundary is exactly the mesh's triangles.
Tetrahedralization tetrahedralize(const TriMesh& welded, const std::string& program, double timeout_seconds);

}  // namespace frep::convert_detail
