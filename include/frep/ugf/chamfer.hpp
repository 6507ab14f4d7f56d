// Chamfers between two faces A and B (docs/ugf.md, "Chamfers"), of an intersection (a convex edge of
// the solid A <= 0 and B <= 0) or of a union (a concave edge of A <= 0 or B <= 0).
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/ugf/edge_frame.hpp"

namespace frep::ugf {

// The size of a chamfer, in one of the four ways a drawing gives it.
struct Chamfer {
  enum class Kind {
    Inset,     // h: the chamfer face's distance from the edge, along the bisector
    Setback,   // s: the distance from the edge to where the chamfer meets each face, along it
    Width,     // w: the width of the chamfer face; w = 2 s cos(phi/2), h = (w/2) tan(phi/2)
    Setbacks,  // sA on face A, sB on face B (asymmetric)
  };
  Kind kind = Kind::Inset;
  float a = 0;  // h, s, w or sA
  float b = 0;  // sB for Setbacks
  // false: max(A, B, C) (min for unions), exact inside (outside for unions) and a bound across
  // the two new edges. true: the max over the two wedges (A, C) and (C, B), each made
  // distance-preserving, which is exact on both sides for planes.
  bool exact = false;

  static Chamfer inset(float h) { return {Kind::Inset, h, 0, false}; }
  static Chamfer setback(float s) { return {Kind::Setback, s, 0, false}; }
  static Chamfer width(float w) { return {Kind::Width, w, 0, false}; }
  static Chamfer setbacks(float sA, float sB) { return {Kind::Setbacks, sA, sB, false}; }
  // The same size, distance-preserving.
  Chamfer distance_preserving() const {
    Chamfer c = *this;
    c.exact = true;
    return c;
  }
};

// Chamfered intersection: max(A, B, C) with the chamfer plane C = Sn + h (symmetric; h from the
// size as above) or C = (sA A + sB B + sA sB sin(phi)) / w, w = sqrt(sA^2 + sB^2 + 2 sA sB c)
// (asymmetric). For planes: exact inside the solid, and outside except across the chamfer's two
// edges, where it is a bound; with Chamfer::exact, exact everywhere. Degenerate angles
// (EdgeOptions) give max(A, B).
Expr chamfer_intersection(Expr A, Expr B, const Chamfer& size, const EdgeOptions& opt = {});
Expr chamfer_intersection(const EdgeFrame& f, const Chamfer& size);

// Chamfered union (fills the concave edge): min(A, B, C) with C = Sn - h or
// (sA A + sB B - sA sB sin(phi)) / w; the dual of the intersection form, exact for planes
// outside the solid (everywhere with Chamfer::exact). Degenerate angles give min(A, B).
Expr chamfer_union(Expr A, Expr B, const Chamfer& size, const EdgeOptions& opt = {});
Expr chamfer_union(const EdgeFrame& f, const Chamfer& size);

// The classic 45-degree chamfer min(a, b, (a + b - r) / sqrt(2)) of a union: the c = 0 case of
// chamfer_union with setback r (inset r / sqrt(2)), needing no gradient; for perpendicular faces
// only (for others the setback is not r).
Expr chamfer_union_right_angle(Expr A, Expr B, float r);
// max(a, b, (a + b + r) / sqrt(2)): its intersection counterpart.
Expr chamfer_intersection_right_angle(Expr A, Expr B, float r);

}  // namespace frep::ugf
