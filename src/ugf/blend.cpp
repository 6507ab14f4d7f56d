// Smooth blends (blend.hpp).
#include "frep/ugf/blend.hpp"

#include <algorithm>

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

namespace {
double larger_bound(const Field& a, const Field& b) {
  return a.info.lipschitz > 0 && b.info.lipschitz > 0 ? std::max(a.info.lipschitz, b.info.lipschitz) : 0.0;
}
// How far below min(a, b) each kind reaches (its value where a = b).
double depth(float k, Blend blend) {
  switch (blend) {
    case Blend::Quadratic: return k / 4.0;
    case Blend::Cubic: return k / 6.0;
    case Blend::Exponential: return k * 0.6931471805599453;
    case Blend::Root: return k / 2.0;
  }
  return k;
}
}  // namespace

Field smooth_union(const Field& a, const Field& b, float k, Blend blend) {
  // 1e-5: room for the f32 evaluation of the blend term.
  return Field(smooth_union(a.expr, b.expr, k, blend),
               union_within_info(a.info, b.info, depth(k, blend) * (1 + 1e-5), larger_bound(a, b)));
}
Field smooth_intersection(const Field& a, const Field& b, float k, Blend blend) {
  FieldInfo info = intersection_info(a.info, b.info);  // at least max(a, b)
  info.lipschitz = larger_bound(a, b);
  return Field(smooth_intersection(a.expr, b.expr, k, blend), info);
}
Field smooth_difference(const Field& a, const Field& b, float k, Blend blend) {
  FieldInfo info = difference_info(a.info, b.info);
  info.lipschitz = larger_bound(a, b);
  return Field(smooth_difference(a.expr, b.expr, k, blend), info);
}

}  // namespace frep::ugf
