// Booleans of unit gradient fields (docs/ugf.md, "Booleans"): plain min/max, the distance-preserving
// forms for any dihedral angle, and the right-angle forms. A = 0 and B = 0 are the two surfaces,
// inside negative; c = dot(grad A, grad B) = cos(phi), phi the angle between the outward normals
// (a box edge has phi = 90 degrees). c is built with the symbolic gradient (derivative.hpp).
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/model/field.hpp"
#include "frep/ugf/edge_frame.hpp"

namespace frep::ugf {

// Plain booleans: max(A, B), min(A, B), max(A, -B). UGF in, UGF out. With signed distances in:
// the intersection is exact inside and outside the edge's normal cone, the union exact outside
// and inside the (negated) cone, the difference like the intersection. Inside the cones they
// are bounds: never larger in magnitude than the true distance.
Expr intersect(Expr A, Expr B);
Expr unite(Expr A, Expr B);
Expr subtract(Expr A, Expr B);

// Distance-preserving intersection: inside the edge's normal cone (B - cA > 0 and A - cB > 0)
// the distance to the edge, sqrt(A^2 + B^2 - 2cAB) / sin(phi) (evaluated as the length of
// (A, (B - cA) / sin(phi)), equal and better conditioned in f32); elsewhere max(A, B). The exact
// signed distance of the wedge for planes at any angle; for curved inputs c varies and the cone
// test is first-order (exact at the edge). Near phi = 0 or 180 degrees (EdgeOptions) it falls
// back to max(A, B). Its gradient is finite everywhere (0 on the edge itself).
Expr intersect_exact(Expr A, Expr B, const EdgeOptions& opt = {});
// Union by duality, -intersect_exact(-A, -B): exact for planes at any angle.
Expr unite_exact(Expr A, Expr B, const EdgeOptions& opt = {});
// intersect_exact(A, -B).
Expr subtract_exact(Expr A, Expr B, const EdgeOptions& opt = {});

// Right-angle forms (c = 0, e.g. box edges), without any gradient:
// min(max(A, B), 0) + length(max(A, 0), max(B, 0)), exact for perpendicular planes everywhere
// (exact outside, and max(A, B) inside is exact anyway). Its gradient is finite everywhere
// (0 on the edge itself, where the length is sqrt(0)).
Expr intersect_right_angle(Expr A, Expr B);
// max(min(A, B), 0) - length(min(A, 0), min(B, 0)): exact for perpendicular planes.
Expr unite_right_angle(Expr A, Expr B);
// intersect_right_angle(A, -B).
Expr subtract_right_angle(Expr A, Expr B);

// The same on fields, carrying their facts (frep/model/field.hpp). Each intersection is at least
// max(A, B) and each union equals min(A, B) outside both solids, so the boxes and growths are
// those of max and min (csg.hpp); their Lipschitz bounds are not proven and stay unknown.
Field intersect_exact(const Field& A, const Field& B, const EdgeOptions& opt = {});
Field unite_exact(const Field& A, const Field& B, const EdgeOptions& opt = {});
Field subtract_exact(const Field& A, const Field& B, const EdgeOptions& opt = {});
Field intersect_right_angle(const Field& A, const Field& B);
Field unite_right_angle(const Field& A, const Field& B);
Field subtract_right_angle(const Field& A, const Field& B);

}  // namespace frep::ugf
