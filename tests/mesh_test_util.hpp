// Shared helpers for the mesh tests: small meshes made in code and the shared-data location.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "frep/mesh/mesh.hpp"

namespace frep::test {

inline std::string shared_mesh_dir() { return FREP_SOURCE_DIR "/../shared/data/meshes"; }
inline bool have_shared_meshes() { return std::filesystem::exists(shared_mesh_dir() + "/MANIFEST.tsv"); }

#define FREP_REQUIRE_SHARED_MESHES()                                                         \
  do {                                                                                       \
    if (!::frep::test::have_shared_meshes())                                                 \
      GTEST_SKIP() << "../shared/data/meshes is absent; skipping the real-mesh test";        \
  } while (0)

// Axis-aligned box [lo, hi], 8 vertices, 12 outward-facing triangles.
inline TriMesh make_box(Vec3 lo = {-1, -1, -1}, Vec3 hi = {1, 1, 1}) {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (std::uint32_t t = 0; t < 12; ++t)
    m.add_triangle(f[t][0], f[t][1], f[t][2], t, 0);
  return m;
}

// Box subdivided into n x n quads per side (2n^2 triangles per face), welded, outward.
TriMesh make_fine_box(int n, Vec3 lo = {-1, -1, -1}, Vec3 hi = {1, 1, 1});
// Unit-radius-`r` sphere from a subdivided icosahedron (20 * 4^level triangles), welded, outward.
TriMesh make_sphere(int level, double r = 1.0);

}  // namespace frep::test
