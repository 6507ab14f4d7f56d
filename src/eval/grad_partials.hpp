// The partial derivatives of each op (private to src/eval): the gradient evaluator's scalar
// path, shared by the interpreter (grad_eval.cpp) and the JIT's calls (jit_codegen.cpp), so both
// compute the same bits.
#pragma once

#include <cmath>

#include "frep/expr/opcode.hpp"
#include "frep/expr/semantics.hpp"

namespace frep {
namespace grad_detail {

// Derivative of op at (a, b) given value v: returns (dv/da, dv/db).
inline void partials(Op op, float a, float b, float v, float& pa, float& pb) {
  pa = 0;
  pb = 0;
  switch (op) {
    case Op::Neg: pa = -1; break;
    case Op::Abs: pa = a < 0 ? -1.0f : 1.0f; break;
    case Op::Recip: pa = -1.0f / (a * a); break;
    case Op::Sqrt: pa = v == 0 ? 0.0f : 0.5f / v; break;
    case Op::Square: pa = 2 * a; break;
    case Op::Sin: pa = std::cos(a); break;
    case Op::Cos: pa = -std::sin(a); break;
    case Op::Tan: pa = 1 + v * v; break;
    case Op::Asin: pa = 1.0f / std::sqrt(1 - a * a); break;
    case Op::Acos: pa = -1.0f / std::sqrt(1 - a * a); break;
    case Op::Atan: pa = 1.0f / (1 + a * a); break;
    case Op::Exp: pa = v; break;
    case Op::Ln: pa = 1.0f / a; break;
    case Op::Add: pa = 1; pb = 1; break;
    case Op::Sub: pa = 1; pb = -1; break;
    case Op::Mul: pa = b; pb = a; break;
    case Op::Div: pa = 1.0f / b; pb = -a / (b * b); break;
    case Op::Atan2: {
      const float d = a * a + b * b;  // atan2(y = a, x = b)
      pa = b / d;
      pb = -a / d;
      break;
    }
    case Op::Min:
      if (std::isnan(v)) pa = pb = v;
      else if (a < b) pa = 1;
      else pb = 1;
      break;
    case Op::Max:
      if (std::isnan(v)) pa = pb = v;
      else if (a > b) pa = 1;
      else pb = 1;
      break;
    case Op::Mod:
      pa = 1;
      pb = -std::floor(a / std::fabs(b)) * (b < 0 ? -1.0f : 1.0f);
      break;
    case Op::And:
      if (a == 0) pa = 1; else pb = 1;
      break;
    case Op::Or:
      if (a != 0) pa = 1; else pb = 1;
      break;
    default:  // floor, ceil, round, compare, not: piecewise constant
      break;
  }
}

// One point through op on the scalar path: value v and gradient d from the arguments' values
// and gradients (has_a/has_b false where an argument is an immediate or absent: no gradient).
inline void grad_lane(Op op, float a, const float* da, bool has_a, float b, const float* db, bool has_b, float& v,
                      float* d) {
  v = op_eval<float>(op, a, b);
  float pa, pb;
  partials(op, a, b, v, pa, pb);
  for (int k = 0; k < 3; ++k) {
    // A zero partial must not turn an infinite or NaN argument gradient into NaN.
    float t = 0;
    if (pa != 0 && has_a) t += pa * da[k];
    if (pb != 0 && has_b) t += pb * db[k];
    d[k] = t;
  }
}

}  // namespace grad_detail
}  // namespace frep
