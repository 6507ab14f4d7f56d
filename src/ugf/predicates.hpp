// Predicates and selects for the UGF library, built from frep opcodes only (compare/and/or/not),
// so every result can be written to `.vm`. A predicate is an expression that is non-zero exactly
// where the condition holds (NaN counts as non-zero, as in and/or/not).
#pragma once

#include <cmath>

#include "frep/expr/expr.hpp"

namespace frep::ugf::detail {

// 1 where x > 0, 0 elsewhere.
inline Expr positive(Expr x) { return max(compare(x, 0.0f), 0.0f); }
// Non-zero where both hold.
inline Expr both(Expr p, Expr q) { return logical_and(p, q); }
// p ? a : b with the chosen side's gradient everywhere (see if_nonzero_else). `p` must have
// gradient 0 (built from compare/not/and/or of predicates), so that its side contributes nothing.
inline Expr select(Expr p, Expr a, Expr b) { return if_nonzero_else(p, a, b); }
// sqrt of a quantity that is non-negative in exact arithmetic but may round below zero.
inline Expr safe_sqrt(Expr x) { return sqrt(max(x, 0.0f)); }
inline Expr length2(Expr a, Expr b) { return sqrt(square(a) + square(b)); }

inline constexpr float kPi = 3.14159265358979323846f;
inline float radians(float degrees) { return degrees * (kPi / 180.0f); }

}  // namespace frep::ugf::detail
