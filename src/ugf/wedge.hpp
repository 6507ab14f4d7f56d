// The distance-preserving corner shared by the exact booleans and the exact chamfers: max(A, B)
// corrected inside the edge's normal cone to the distance to the edge.
#pragma once

#include "frep/expr/expr.hpp"

namespace frep::ugf::detail {

// For planes A and B with c = cos(phi), sin_phi = sin(phi) (> 0): inside the cone B - cA > 0,
// A - cB > 0 the distance to the edge sqrt(A^2 + B^2 - 2cAB) / sin(phi), elsewhere max(A, B);
// max(A, B) wherever `valid` is zero. `sin_floor` > 0 keeps the division finite everywhere.
Expr exact_wedge(Expr A, Expr B, Expr c, Expr sin_phi, Expr valid, float sin_floor);

}  // namespace frep::ugf::detail
