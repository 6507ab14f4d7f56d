// The clearance of two meshes: compare_meshes (frep/mesh/mesh_pair.hpp) settles whether they are
// apart, and the exact gap then, which boxes could not prove (S = A + B is constant along the
// whole shortest segment). Only the depth of an interference is left to the interval search
// (find_clearance), which the comparison starts where the bodies are known to meet.
#pragma once

#include "frep/mesh/mesh_pair.hpp"
#include "frep/ugf/clearance.hpp"

namespace frep::ugf {

// `opt` readied for the search of how deep two meshes interfere, given their comparison `pair`
// (not apart): seeded with every contact listed where the surfaces meet, else with the point of
// the nested surface nearest the other (it lies inside that one). `in_place`: neither mesh is moved,
// so that A and B are exact up to their rounding to float and S is 2-Lipschitz, which bounds a
// box from one evaluation at its centre; moved meshes keep interval bounds, which allow for the
// rounding of the moved points.
ClearanceOptions mesh_interference_options(const MeshPairResult& pair, bool in_place, ClearanceOptions opt = {});

// Whether two meshes only touch: their surfaces meet without crossing, neither nests in the
// other, and the search `r` found no interference deeper than `tolerance`.
bool only_touching(const MeshPairResult& pair, const ClearanceResult& r, double tolerance);

}  // namespace frep::ugf
