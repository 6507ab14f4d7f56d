// Chamfers (chamfer.hpp): a third plane C through the solid near the edge, written in the edge
// frame, combined with max (intersections) or min (unions), or corner by corner with the
// distance-preserving wedge.
#include "frep/ugf/chamfer.hpp"

#include <cmath>

#include "frep/error.hpp"
#include "ugf/predicates.hpp"
#include "ugf/wedge.hpp"

namespace frep::ugf {

using namespace detail;

namespace {

// The chamfer plane and the cosines and sines of its angles to A and to B (the sines directly,
// not as sqrt(1 - c^2), which loses precision at small angles).
struct Plane {
  Expr C, cAC, cBC, sAC, sBC;
};

// sign = +1 for an intersection (C cuts into the solid), -1 for a union (C fills the edge).
Plane chamfer_plane(const EdgeFrame& f, const Chamfer& s, float sign) {
  const Expr ch = max(f.cos_half, f.guard);
  switch (s.kind) {
    case Chamfer::Kind::Inset:
    case Chamfer::Kind::Setback:
    case Chamfer::Kind::Width: {
      Expr h = f.A.graph().c(s.a);
      if (s.kind == Chamfer::Kind::Setback) h = s.a * f.sin_half;
      if (s.kind == Chamfer::Kind::Width) h = (0.5f * s.a) * f.sin_half / ch;
      // The bisector's normal makes the angle phi/2 with each face's.
      return {f.Sn + sign * h, f.cos_half, f.cos_half, f.sin_half, f.sin_half};
    }
    case Chamfer::Kind::Setbacks: {
      const float sA = s.a, sB = s.b;
      const Expr sin_phi = 2.0f * f.sin_half * f.cos_half;
      const Expr w = safe_sqrt(sA * sA + sB * sB + (2.0f * sA * sB) * f.c);
      const Expr wf = max(w, 1e-30f);
      const Expr C = (sA * f.A + sB * f.B + (sign * sA * sB) * sin_phi) / wf;
      // |nA x (sA nA + sB nB)| / w = sB sin(phi) / w.
      return {C, (sA + sB * f.c) / wf, (sA * f.c + sB) / wf, sB * sin_phi / wf, sA * sin_phi / wf};
    }
  }
  FREP_ASSERT(false, "unknown chamfer kind");
  return {f.Sn, f.c, f.c, f.sin_half, f.sin_half};
}

// The convex chamfered wedge max(A, B, C), or its distance-preserving form.
Expr chamfered_wedge(Expr A, Expr B, const Plane& p, const EdgeFrame& f, bool exact) {
  if (!exact) return max(max(A, B), p.C);
  const float floor = 2.0f * f.guard * f.guard;
  auto corner = [&](Expr P, Expr Q, Expr c, Expr s) { return exact_wedge(P, Q, c, s, positive(s - floor), floor); };
  return max(corner(A, p.C, p.cAC, p.sAC), corner(p.C, B, p.cBC, p.sBC));
}

}  // namespace

Expr chamfer_intersection(const EdgeFrame& f, const Chamfer& size) {
  const Plane p = chamfer_plane(f, size, 1.0f);
  return select(f.valid, chamfered_wedge(f.A, f.B, p, f, size.exact), max(f.A, f.B));
}

Expr chamfer_union(const EdgeFrame& f, const Chamfer& size) {
  // The complement of the union is the convex wedge of -A, -B (same angle) cut by -C.
  const Plane p = chamfer_plane(f, size, -1.0f);
  const Plane neg{-p.C, p.cAC, p.cBC, p.sAC, p.sBC};
  return select(f.valid, -chamfered_wedge(-f.A, -f.B, neg, f, size.exact), min(f.A, f.B));
}

Expr chamfer_intersection(Expr A, Expr B, const Chamfer& size, const EdgeOptions& opt) {
  return chamfer_intersection(edge_frame(A, B, opt), size);
}

Expr chamfer_union(Expr A, Expr B, const Chamfer& size, const EdgeOptions& opt) {
  return chamfer_union(edge_frame(A, B, opt), size);
}

Expr chamfer_union_right_angle(Expr A, Expr B, float r) {
  return min(min(A, B), (A + B - r) * static_cast<float>(M_SQRT1_2));
}

Expr chamfer_intersection_right_angle(Expr A, Expr B, float r) {
  return max(max(A, B), (A + B + r) * static_cast<float>(M_SQRT1_2));
}

}  // namespace frep::ugf
