// The reference semantics of every opcode, on scalars. Constant folding, the point evaluator and
// the conformance tests all use this one definition (float for evaluation, double for tests).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "frep/expr/opcode.hpp"

namespace frep {

template <class T>
inline T op_min(T a, T b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<T>::quiet_NaN();
  return a < b ? a : b;
}
template <class T>
inline T op_max(T a, T b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<T>::quiet_NaN();
  return a > b ? a : b;
}
// Euclidean remainder: result in [0, |b|] (|b| itself only through rounding); NaN for b == 0.
template <class T>
inline T op_mod(T a, T b) {
  T r = std::fmod(a, b);
  return r < 0 ? r + std::fabs(b) : r;
}
template <class T>
inline T op_compare(T a, T b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<T>::quiet_NaN();
  return a < b ? T(-1) : (a > b ? T(1) : T(0));
}

// Evaluates a unary or binary op (b is ignored for unary ops). Leaves are not handled here.
template <class T>
inline T op_eval(Op op, T a, T b) {
  switch (op) {
    case Op::Neg: return -a;
    case Op::Abs: return std::fabs(a);
    case Op::Recip: return T(1) / a;
    case Op::Sqrt: return std::sqrt(a);
    case Op::Square: return a * a;
    case Op::Floor: return std::floor(a);
    case Op::Ceil: return std::ceil(a);
    case Op::Round: return std::round(a);  // halves away from zero
    case Op::Sin: return std::sin(a);
    case Op::Cos: return std::cos(a);
    case Op::Tan: return std::tan(a);
    case Op::Asin: return std::asin(a);
    case Op::Acos: return std::acos(a);
    case Op::Atan: return std::atan(a);
    case Op::Exp: return std::exp(a);
    case Op::Ln: return std::log(a);
    case Op::Not: return a == 0 ? T(1) : T(0);  // NaN counts as non-zero
    case Op::Add: return a + b;
    case Op::Sub: return a - b;
    case Op::Mul: return a * b;
    case Op::Div: return a / b;
    case Op::Atan2: return std::atan2(a, b);
    case Op::Min: return op_min(a, b);
    case Op::Max: return op_max(a, b);
    case Op::Compare: return op_compare(a, b);
    case Op::Mod: return op_mod(a, b);
    case Op::And: return a == 0 ? a : b;
    case Op::Or: return a != 0 ? a : b;
    case Op::VarX:
    case Op::VarY:
    case Op::VarZ:
    case Op::Const:
    case Op::Oracle: break;
  }
  return std::numeric_limits<T>::quiet_NaN();
}

// o[i] = op_eval(op, a[i * a_step], b[i * b_step]) for i < n (a step of 0 repeats one value, an
// immediate), with the op chosen once rather than per value: the path of the vector kernels for
// the ops they leave to the C library, lane by lane.
template <class T>
inline void op_eval_lanes(Op op, T* o, const T* a, std::size_t a_step, const T* b, std::size_t b_step, std::size_t n) {
  auto run = [&](auto f) {
    for (std::size_t i = 0; i < n; ++i) o[i] = f(a[i * a_step], b[i * b_step]);
  };
  switch (op) {
    case Op::Sin: return run([](T x, T y) { return op_eval<T>(Op::Sin, x, y); });
    case Op::Cos: return run([](T x, T y) { return op_eval<T>(Op::Cos, x, y); });
    case Op::Tan: return run([](T x, T y) { return op_eval<T>(Op::Tan, x, y); });
    case Op::Asin: return run([](T x, T y) { return op_eval<T>(Op::Asin, x, y); });
    case Op::Acos: return run([](T x, T y) { return op_eval<T>(Op::Acos, x, y); });
    case Op::Atan: return run([](T x, T y) { return op_eval<T>(Op::Atan, x, y); });
    case Op::Exp: return run([](T x, T y) { return op_eval<T>(Op::Exp, x, y); });
    case Op::Ln: return run([](T x, T y) { return op_eval<T>(Op::Ln, x, y); });
    case Op::Atan2: return run([](T x, T y) { return op_eval<T>(Op::Atan2, x, y); });
    case Op::Mod: return run([](T x, T y) { return op_eval<T>(Op::Mod, x, y); });
    default: return run([op](T x, T y) { return op_eval<T>(op, x, y); });
  }
}

}  // namespace frep
