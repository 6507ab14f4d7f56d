// The gyroid triply periodic surface as a lattice (docs/ugf.md, "Normalization and the gyroid"): an example
// of a field that is not a distance, made usable by normalization.
#pragma once

#include "frep/expr/expr.hpp"

namespace frep::ugf {

// How to turn the raw gyroid g into a distance-like field.
enum class GyroidScale {
  Bound,    // g / (sqrt(3) w): |grad g| <= sqrt(3) w on the surface, a safe underestimate near it
  Sampson,  // g / |grad g|: a unit gradient on the surface, an approximate distance near it
};

// g = sin(wx) cos(wy) + sin(wy) cos(wz) + sin(wz) cos(wx), w = 2 pi / period. On g = 0,
// |grad g| lies in [sqrt(2) w, sqrt(3) w].
Expr gyroid(Graph& g, float period);
// The scaled gyroid gn (see GyroidScale).
Expr gyroid_normalized(Graph& g, float period, GyroidScale scale = GyroidScale::Sampson);
// Network solid gn - bias: one of the two labyrinths, thickened (bias > 0) or thinned (bias < 0).
Expr gyroid_network(Graph& g, float period, float bias, GyroidScale scale = GyroidScale::Sampson);
// Sheet solid |gn| - t/2: a wall of thickness about t around the gyroid surface.
Expr gyroid_sheet(Graph& g, float period, float t, GyroidScale scale = GyroidScale::Sampson);

}  // namespace frep::ugf
