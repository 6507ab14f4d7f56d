// Fields between two bodies A and B (docs/ugf.md, "Two bodies and clearance"): the two-body
// parameter, the surfaces between the bodies, the midsurface and the clearance field.
#pragma once

#include "frep/expr/expr.hpp"

namespace frep::ugf {

// Xi = (A - B) / (A + B): -1 on A's surface, +1 on B's, 0 on the midsurface, and Xi = t exactly
// where A / B = (1 + t) / (1 - t). Defined where A + B != 0: everywhere outside both bodies
// when they are disjoint signed distances (A + B >= gap > 0 there). Not a distance.
Expr two_body(Expr A, Expr B);

// u = (Xi + 1) / 2: 0 on A, 1 on B, for grading thickness or lattice density between bodies.
Expr two_body_parameter(Expr A, Expr B);

// The surface "t of the way" from A (t = -1) to B (t = +1), the level set Xi = t: the zero set
// of (1 - t) A - (1 + t) B, Sampson-normalized so that it is a unit gradient field on the
// surface and approximates the distance to it nearby.
Expr between(Expr A, Expr B, float t);

// D / 2 = (A - B) / 2, zero on the midsurface (the surface t = 0). For signed distances it
// approximates the distance to the midsurface; exact for two parallel planes.
Expr midsurface(Expr A, Expr B);

// S = A + B. For signed distances it is constant along the shortest segment between the bodies
// and its minimum over space is the gap (> 0) or minus the interference depth (< 0):
// find_clearance (clearance.hpp) minimizes it. This is not the Hausdorff distance, which is
// sup |d1 - d2| over unsigned distances.
Expr clearance_field(Expr A, Expr B);

}  // namespace frep::ugf
