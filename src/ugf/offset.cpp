// Offsets and shells (offset.hpp).
#include "frep/ugf/offset.hpp"

#include <algorithm>

#include "frep/ugf/normalize.hpp"

namespace frep::ugf {

Expr offset(Expr F, float r) { return F - r; }
Expr shell(Expr F, float t) { return abs(F) - 0.5f * t; }
Expr shell_biased(Expr F, float t, float b) { return abs(F + 0.5f * b * t) - 0.5f * t; }
Expr shell_inward(Expr F, float t) { return max(F, -F - t); }
Expr shell_outward(Expr F, float t) { return max(-F, F - t); }
Expr shell_variable(Expr F, Expr T) { return normalize(abs(F) - 0.5f * T); }

namespace {
// A wall whose inside lies where F < reach: F's facts offset by reach, no longer a distance
// (the wall's far side is not where |F| says).
Field wall(Expr e, const Field& F, double reach) {
  FieldInfo info = offset_info(F.info, reach * (1 + 1e-6));  // f32 rounding of the constants
  info.growth = std::min(info.growth, Growth::Box);
  return Field(e, info);
}
}  // namespace

Field offset(const Field& F, float r) { return Field(offset(F.expr, r), offset_info(F.info, r)); }
Field shell(const Field& F, float t) { return wall(shell(F.expr, t), F, 0.5 * t); }
Field shell_biased(const Field& F, float t, float b) { return wall(shell_biased(F.expr, t, b), F, 0.5 * t * (1.0 - b)); }
Field shell_inward(const Field& F, float t) { return wall(shell_inward(F.expr, t), F, 0); }
Field shell_outward(const Field& F, float t) { return wall(shell_outward(F.expr, t), F, t); }

}  // namespace frep::ugf
