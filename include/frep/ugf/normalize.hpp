// Gradient normalization (docs/ugf.md, "Normalization and the gyroid").
#pragma once

#include "frep/expr/expr.hpp"

namespace frep::ugf {

// Sampson normalization F / |grad F|, with the symbolic gradient (derivative.hpp). For a field F
// that is not a distance, this has a unit gradient on F's zero set and approximates the distance
// near it, so that offsets and shells of it behave. The gradient length is floored at
// `min_gradient`, so the value stays finite at F's critical points (far from the surface, where
// the result means nothing).
Expr normalize(Expr F, float min_gradient = 1e-12f);

}  // namespace frep::ugf
