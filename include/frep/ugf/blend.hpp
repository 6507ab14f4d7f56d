// Smooth blends (docs/ugf.md, "Smooth blends": the smooth minimum family). These are bounds, not unit
// gradient fields: with signed distances in, the gradient is a convex combination of the two
// input gradients, so its length is at most 1 and the value never overestimates the distance
// to the blended surface (it underestimates it inside the blend). Offsetting a blend therefore
// does not give an exact offset; re-normalize (normalize.hpp) if a UGF is needed near the surface.
#pragma once

#include "frep/expr/expr.hpp"
#include "frep/model/field.hpp"

namespace frep::ugf {

enum class Blend {
  // h = max(k - |a - b|, 0) / k; min(a, b) - h^2 k / 4. Equals min where |a - b| >= k.
  Quadratic,
  // min(a, b) - h^3 k / 6 with the same h: C2 where the blend starts. Equals min where |a - b| >= k.
  Cubic,
  // -k ln(exp(-a/k) + exp(-b/k)), computed as min(a, b) - k ln(1 + exp(-|a - b| / k)):
  // infinitely smooth, never equal to min (k ln 2 below it where a = b).
  Exponential,
  // (a + b - sqrt((a - b)^2 + k^2)) / 2: k/2 below min where a = b, approaches min as 1/|a - b|.
  Root,
};

// Smooth union of blend thickness k > 0: at most min(a, b).
Expr smooth_union(Expr a, Expr b, float k, Blend blend = Blend::Quadratic);
// Smooth intersection -smooth_union(-a, -b, k): at least max(a, b).
Expr smooth_intersection(Expr a, Expr b, float k, Blend blend = Blend::Quadratic);
// Smooth difference smooth_intersection(a, -b, k).
Expr smooth_difference(Expr a, Expr b, float k, Blend blend = Blend::Quadratic);

// The same on fields, carrying their facts (frep/model/field.hpp): the larger Lipschitz bound
// (the gradient is a convex combination); a smooth union's box is the union's grown by how far
// below min(a, b) the blend goes (k/4, k/6, k ln 2, k/2 by kind); the others' as max's.
Field smooth_union(const Field& a, const Field& b, float k, Blend blend = Blend::Quadratic);
Field smooth_intersection(const Field& a, const Field& b, float k, Blend blend = Blend::Quadratic);
Field smooth_difference(const Field& a, const Field& b, float k, Blend blend = Blend::Quadratic);

}  // namespace frep::ugf
