// Offsets and shells (offset.hpp).
#include "frep/ugf/offset.hpp"

#include "frep/ugf/normalize.hpp"

namespace frep::ugf {

Expr offset(Expr F, float r) { return F - r; }
Expr shell(Expr F, float t) { return abs(F) - 0.5f * t; }
Expr shell_biased(Expr F, float t, float b) { return abs(F + 0.5f * b * t) - 0.5f * t; }
Expr shell_inward(Expr F, float t) { return max(F, -F - t); }
Expr shell_outward(Expr F, float t) { return max(-F, F - t); }
Expr shell_variable(Expr F, Expr T) { return normalize(abs(F) - 0.5f * T); }

}  // namespace frep::ugf
