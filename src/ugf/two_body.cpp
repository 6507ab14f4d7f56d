// Two-body fields (two_body.hpp).
#include "frep/ugf/two_body.hpp"

#include "frep/ugf/normalize.hpp"

namespace frep::ugf {

Expr two_body(Expr A, Expr B) { return (A - B) / (A + B); }
Expr two_body_parameter(Expr A, Expr B) { return (two_body(A, B) + 1.0f) * 0.5f; }
Expr between(Expr A, Expr B, float t) { return normalize((1.0f - t) * A - (1.0f + t) * B); }
Expr midsurface(Expr A, Expr B) { return (A - B) * 0.5f; }
Expr clearance_field(Expr A, Expr B) { return A + B; }

}  // namespace frep::ugf
