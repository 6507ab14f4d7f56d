// The mesh-distance query structure (private to MeshDistance) and its SIMD kernels (Highway,
// dispatched at run time).
#pragma once

#include <cstddef>
#include <cstdint>

#include "frep/math/vec.hpp"

namespace frep::mesh_detail {

// The query structure, 8 wide so one SIMD register of doubles (AVX-512; two on AVX2, four on
// SSE4) tests eight boxes or eight triangles at once: a shallower tree than 4 wide, about 12% less
// time per query. Built from the binary BVH by pulling descendants up.
constexpr int kWidth = 8;
struct alignas(64) WideNode {
  double lo[3][kWidth], hi[3][kWidth];  // child boxes; an empty slot has lo = +inf, hi = -inf
  std::int32_t child[kWidth];           // >= 0: inner node; < 0: leaf, packets ~child, ~child + 1, ...
  std::uint32_t packets[kWidth];        // number of packets of a leaf child
};
// Four triangles, structure of arrays. Padding lanes repeat the packet's last triangle. Every
// double array starts on a 32-byte boundary: the kernels load them with aligned loads.
struct alignas(64) TriPacket {
  double a[3][kWidth], b[3][kWidth], c[3][kWidth];  // corners
  double n[3][kWidth];                              // cross(b - a, c - a); zero if degenerate
  double inv_n2[kWidth];                            // 1 / |n|^2, zero if degenerate
  double inv_e2[3][kWidth];  // 1 / |edge k|^2 (edge k joins corners k and k+1), zero if a point
  double real[kWidth];        // 1 for a triangle, 0 for padding (sums must not count it twice)
  std::uint32_t tri[kWidth];  // leaf-order triangle index
};
static_assert(offsetof(TriPacket, real) % 64 == 0 && offsetof(TriPacket, inv_e2) % 64 == 0 &&
                  offsetof(TriPacket, inv_n2) % 64 == 0,
              "aligned loads of TriPacket's arrays");
// Winding-number data of a wide node's children: far from a child, its triangles act as one
// dipole (the area-weighted sum of their normals at their area-weighted centroid).
struct alignas(64) WideDipoles {
  double center[3][kWidth], area_normal[3][kWidth];
  double far2[kWidth];  // (beta * radius)^2: the dipole is used beyond this squared distance
};

// The triangle nearest to p over the wide BVH rooted at nodes[0]: its leaf-order index, with its
// squared distance in `d2`; among triangles at the same (computed) distance, the smallest index,
// so that the answer does not depend on the search order. Only triangles at most the incoming
// `d2` away are considered (pass INFINITY for all: a bound from a nearby query's triangle saves
// most of the search); returns UINT32_MAX if there is none.
std::uint32_t nearest_triangle(const WideNode* nodes, const TriPacket* packets, const Vec3& p, double& d2);

// The triangle a ray o + t dir first meets with t in [0, t_max] (t_max receives its t): its
// leaf-order index, or UINT32_MAX if none. Ties go to the smallest index.
std::uint32_t first_hit(const WideNode* nodes, const TriPacket* packets, const Vec3& o, const Vec3& dir, double& t_max);

// Sum of the solid angles of the triangles seen from p (4 pi times the winding number), with
// the dipole approximation for the children of `nodes` farther than their `far2`.
double solid_angle_sum(const WideNode* nodes, const WideDipoles* dipoles, const TriPacket* packets, const Vec3& p);

}  // namespace frep::mesh_detail
