// Medial-axis tracking through booleans (docs/ugf.md, "Medial-axis tracking"): a
// field carried together with M, a signed distance-like field to its crease set (where its
// gradient jumps). Useful for variable fillets, thickness analysis and "distance to the middle
// of the wall". This is the crease of the UGF; where a boolean is not a signed distance it
// differs from the Euclidean medial axis.
#pragma once

#include "frep/expr/expr.hpp"

namespace frep::ugf {

struct Tracked {
  Expr f;  // the field
  Expr m;  // distance to f's crease set (+inf when there is none); compared by magnitude
};

// A field with no crease (a plane): M = +inf.
Tracked track_plane(Expr f);
// A field with a known crease distance.
Tracked track(Expr f, Expr m);
// The sphere |p - c| - r, whose crease is its center: M = |p - c|.
Tracked track_sphere(Graph& g, float cx, float cy, float cz, float r);

// Offsets and negation keep M.
Tracked offset(const Tracked& a, float r);
Tracked negate(const Tracked& a);
// |F| - t/2 adds F = 0 to the crease set: M = |M| <= |F| ? M : F.
Tracked shell(const Tracked& a, float t);

// max / min / max(A, -B). With w the side that wins at the point and
// Mnew = (A - B) / |grad A - grad B| (the first-order distance to the tie A = B):
// M = |M_w| <= |Mnew| ? M_w : Mnew. Where the two gradients coincide there is no new crease
// (Mnew = +inf). Exact for boxes built from planes (M = distance to the diagonal planes).
Tracked intersect(const Tracked& a, const Tracked& b);
Tracked unite(const Tracked& a, const Tracked& b);
Tracked subtract(const Tracked& a, const Tracked& b);

}  // namespace frep::ugf
