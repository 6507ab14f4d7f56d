// Offsets and shells of unit gradient fields (docs/ugf.md, "Offsets and shells"). Inside is negative.
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/model/field.hpp"

namespace frep::ugf {

// F - r: grows the solid by r (shrinks it for r < 0). Keeps a unit gradient. For a signed
// distance F it is exact outside the grown solid, and everywhere for a sphere; corners offset
// the way F was built: a max corner mitred, a distance-preserving corner rounded, a chamfer
// bevelled.
Expr offset(Expr F, float r);

// |F| - t/2: a wall of thickness t centred on F's surface. Exact where offsetting F by +-t/2 is
// (everywhere for a sphere or a plane); its crease is F's surface.
Expr shell(Expr F, float t);

// |F + b t/2| - t/2, b in [-1, 1]: a wall of thickness t whose middle sits at F = -b t/2;
// b = +1 puts the whole wall inside F's solid, b = -1 outside, b = 0 is shell().
Expr shell_biased(Expr F, float t, float b);

// max(F, -F - t): the wall of thickness t just inside F's surface (hollowing for printing).
// The same field as shell_biased(F, t, 1).
Expr shell_inward(Expr F, float t);
// max(-F, F - t): the wall of thickness t just outside F's surface.
Expr shell_outward(Expr F, float t);

// A wall of variable thickness T(p) (any field, e.g. from two_body_parameter), centred on F's
// surface and re-normalized: (|F| - T/2) / |grad(|F| - T/2)|. Unit gradient on its surface, an
// approximate distance near it; equal to shell(F, t) for a constant T = t.
Expr shell_variable(Expr F, Expr T);

// The same on fields, carrying their facts (frep/model/field.hpp): F's Lipschitz bound, and its
// box grown by as far as the result's inside reaches beyond F's (r for an offset, t/2 for a
// shell, t outward) when F's growth is known.
Field offset(const Field& F, float r);
Field shell(const Field& F, float t);
Field shell_biased(const Field& F, float t, float b);
Field shell_inward(const Field& F, float t);
Field shell_outward(const Field& F, float t);

}  // namespace frep::ugf
