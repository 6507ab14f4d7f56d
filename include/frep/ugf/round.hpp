// Rounds (fillets) of radius r between two faces A and B (docs/ugf.md, "Rounds").
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/ugf/edge_frame.hpp"

namespace frep::ugf {

// Rounded intersection: with Sr = Sn + r / cos(phi/2), inside the cone |Dn| < Sr tan(phi/2) the
// value is sqrt(Sr^2 + Dn^2) - r (distance to the arc), elsewhere max(A, B). The exact signed
// distance for planes at any angle, inside and out; for curved faces the arc follows the frame
// to first order. Degenerate angles (EdgeOptions) give max(A, B).
Expr round_intersection(Expr A, Expr B, float r, const EdgeOptions& opt = {});
Expr round_intersection(const EdgeFrame& f, float r);

// Rounded union (a fillet in the concave edge): Sr = r / cos(phi/2) - Sn; inside the cone the
// value is r - sqrt(Sr^2 + Dn^2), elsewhere min(A, B). Exact for planes at any angle.
Expr round_union(Expr A, Expr B, float r, const EdgeOptions& opt = {});
Expr round_union(const EdgeFrame& f, float r);

}  // namespace frep::ugf
