// Plain, distance-preserving and right-angle booleans (boolean.hpp).
#include "frep/ugf/boolean.hpp"

#include "ugf/predicates.hpp"
#include "ugf/wedge.hpp"

namespace frep::ugf {

using namespace detail;

Expr intersect(Expr A, Expr B) { return max(A, B); }
Expr unite(Expr A, Expr B) { return min(A, B); }
Expr subtract(Expr A, Expr B) { return max(A, -B); }

namespace {
Expr sin_phi(const EdgeFrame& f) { return 2.0f * f.sin_half * f.cos_half; }
}  // namespace

Expr intersect_exact(Expr A, Expr B, const EdgeOptions& opt) {
  const EdgeFrame f = edge_frame(A, B, opt);
  return exact_wedge(A, B, f.c, sin_phi(f), f.valid, 2.0f * f.guard * f.guard);
}

Expr unite_exact(Expr A, Expr B, const EdgeOptions& opt) {
  // The complement's wedge has normals -grad A, -grad B: the same c.
  const EdgeFrame f = edge_frame(A, B, opt);
  return -exact_wedge(-A, -B, f.c, sin_phi(f), f.valid, 2.0f * f.guard * f.guard);
}

Expr subtract_exact(Expr A, Expr B, const EdgeOptions& opt) { return intersect_exact(A, -B, opt); }

// min and max return their second argument on a tie: 0 first, so that exactly on a face's
// plane (A == 0, common for axis-aligned planes at grid points) the gradient is the face's, not
// that of the constant.
Expr intersect_right_angle(Expr A, Expr B) {
  return min(0.0f, max(A, B)) + length2(max(A, 0.0f), max(B, 0.0f));
}

Expr unite_right_angle(Expr A, Expr B) {
  return max(0.0f, min(A, B)) - length2(min(A, 0.0f), min(B, 0.0f));
}

Expr subtract_right_angle(Expr A, Expr B) { return intersect_right_angle(A, -B); }

namespace {
FieldInfo without_bound(FieldInfo f) {
  f.lipschitz = 0;
  return f;
}
}  // namespace

Field intersect_exact(const Field& A, const Field& B, const EdgeOptions& opt) {
  return Field(intersect_exact(A.expr, B.expr, opt), without_bound(intersection_info(A.info, B.info)));
}
Field unite_exact(const Field& A, const Field& B, const EdgeOptions& opt) {
  return Field(unite_exact(A.expr, B.expr, opt), without_bound(union_info(A.info, B.info)));
}
Field subtract_exact(const Field& A, const Field& B, const EdgeOptions& opt) {
  return Field(subtract_exact(A.expr, B.expr, opt), without_bound(difference_info(A.info, B.info)));
}
Field intersect_right_angle(const Field& A, const Field& B) {
  return Field(intersect_right_angle(A.expr, B.expr), without_bound(intersection_info(A.info, B.info)));
}
Field unite_right_angle(const Field& A, const Field& B) {
  return Field(unite_right_angle(A.expr, B.expr), without_bound(union_info(A.info, B.info)));
}
Field subtract_right_angle(const Field& A, const Field& B) {
  return Field(subtract_right_angle(A.expr, B.expr), without_bound(difference_info(A.info, B.info)));
}

}  // namespace frep::ugf
