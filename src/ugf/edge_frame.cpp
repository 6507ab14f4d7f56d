// The edge frame (edge_frame.hpp) and the distance-preserving corner (wedge.hpp).
#include "frep/ugf/edge_frame.hpp"

#include <cmath>

#include "frep/expr/derivative.hpp"
#include "ugf/predicates.hpp"
#include "ugf/wedge.hpp"

namespace frep::ugf {

using namespace detail;

EdgeFrame edge_frame(Expr A, Expr B, const EdgeOptions& opt) {
  const Expr c = grad_dot(A, B);
  const Expr cos_half = safe_sqrt((1.0f + c) * 0.5f);
  const Expr sin_half = safe_sqrt((1.0f - c) * 0.5f);
  const float guard = std::sin(radians(opt.min_angle_degrees) * 0.5f);
  const Expr valid = both(positive(sin_half - guard), positive(cos_half - guard));
  const Expr S = A + B, D = A - B;
  const Expr Sn = S / (2.0f * max(cos_half, guard));
  const Expr Dn = D / (2.0f * max(sin_half, guard));
  return EdgeFrame{A, B, c, cos_half, sin_half, S, D, Sn, Dn, valid, guard};
}

namespace detail {

Expr exact_wedge(Expr A, Expr B, Expr c, Expr sin_phi, Expr valid, float sin_floor) {
  // sqrt(A^2 + B^2 - 2cAB) / sin(phi), written as the length of (A, (B - cA) / sin(phi)): the
  // edge's distance in coordinates along A's normal and across it. Equal in exact arithmetic (for
  // c^2 + sin^2 = 1), and far better conditioned in f32: the quadratic form cancels to an error
  // of eps |p|^2 / (distance sin^2), this one to eps |p| / sin.
  const Expr edge = length2(A, (B - c * A) / max(sin_phi, sin_floor));
  const Expr cone = both(positive(B - c * A), positive(A - c * B));
  return select(both(valid, cone), edge, max(A, B));
}

}  // namespace detail
}  // namespace frep::ugf
