// SIMD kernels of the mesh-distance queries (Highway, dispatched at run time).
#pragma once

#include <cstdint>

#include "frep/mesh/mesh_distance.hpp"

namespace frep::mesh_detail {

// A triangle nearest to p over the wide BVH rooted at nodes[0]: its leaf-order index, with its
// squared distance in `d2`. Only triangles strictly nearer than the incoming `d2` are considered
// (pass INFINITY for none); returns UINT32_MAX if there is none.
std::uint32_t nearest_triangle(const WideNode* nodes, const TriPacket* packets, const Vec3& p, double& d2);

// Sum of the solid angles of the triangles seen from p (4 pi times the winding number), with
// the dipole approximation for the children of `nodes` farther than their `far2`.
double solid_angle_sum(const WideNode* nodes, const WideDipoles* dipoles, const TriPacket* packets, const Vec3& p);

}  // namespace frep::mesh_detail
