// Smooth blends (blend.hpp).
#include "frep/ugf/blend.hpp"

#include "frep/error.hpp"

namespace frep::ugf {

Expr smooth_union(Expr a, Expr b, float k, Blend blend) {
  FREP_ASSERT(k > 0, "blend thickness must be positive");
  switch (blend) {
    case Blend::Quadratic: {
      const Expr h = max(k - abs(a - b), 0.0f) / k;
      return min(a, b) - square(h) * (k / 4.0f);
    }
    case Blend::Cubic: {
      const Expr h = max(k - abs(a - b), 0.0f) / k;
      return min(a, b) - square(h) * h * (k / 6.0f);
    }
    case Blend::Exponential:
      return min(a, b) - k * ln(1.0f + exp(abs(a - b) * (-1.0f / k)));
    case Blend::Root:
      return (a + b - sqrt(square(a - b) + k * k)) * 0.5f;
  }
  FREP_ASSERT(false, "unknown blend");
  return a;
}

Expr smooth_intersection(Expr a, Expr b, float k, Blend blend) { return -smooth_union(-a, -b, k, blend); }

Expr smooth_difference(Expr a, Expr b, float k, Blend blend) { return smooth_intersection(a, -b, k, blend); }

}  // namespace frep::ugf
