// Interval arithmetic for every opcode (private; the public entry is frep::interval_op).
#pragma once

#include <algorithm>
#include <cmath>

#include "frep/eval/interval.hpp"
#include "frep/expr/semantics.hpp"

namespace frep::ival {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

inline float down(float v, int ulps = 2) {
  for (int i = 0; i < ulps; ++i) v = std::nextafter(v, -kInf);
  return v;
}
inline float up(float v, int ulps = 2) {
  for (int i = 0; i < ulps; ++i) v = std::nextafter(v, kInf);
  return v;
}
inline bool finite(Interval a) { return std::isfinite(a.lo) && std::isfinite(a.hi); }
inline bool has_zero(Interval a) { return a.lo <= 0.0f && a.hi >= 0.0f; }
inline Interval checked(float lo, float hi) {
  if (std::isnan(lo) || std::isnan(hi)) return Interval::unknown();
  return {lo, hi};
}
// Whether an interior point pair can give NaN although the bounds do not show it.
inline bool add_may_nan(Interval a, Interval b) {  // -inf + inf
  return (a.lo == -kInf && b.hi == kInf) || (a.hi == kInf && b.lo == -kInf);
}
inline bool sub_may_nan(Interval a, Interval b) {  // inf - inf
  return (a.hi == kInf && b.hi == kInf) || (a.lo == -kInf && b.lo == -kInf);
}
inline bool mul_may_nan(Interval a, Interval b) {  // 0 * inf
  return (has_zero(a) && !finite(b)) || (has_zero(b) && !finite(a));
}

inline Interval hull(Interval a, Interval b) {
  if (a.is_unknown() || b.is_unknown()) return Interval::unknown();
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}

// Libm functions that are monotone increasing (decreasing) on the argument interval.
template <class F>
inline Interval increasing(Interval a, F f) {
  return checked(down(f(a.lo)), up(f(a.hi)));
}
template <class F>
inline Interval decreasing(Interval a, F f) {
  return checked(down(f(a.hi)), up(f(a.lo)));
}

// sin on [lo, hi]; `phase` shifts the extrema so the same code serves cos (cos x = sin(x + pi/2)).
inline Interval periodic(Interval a, double phase, float (*f)(float)) {
  if (!finite(a)) return Interval::unknown();
  const double lo = a.lo, hi = a.hi;
  constexpr double kTwoPi = 6.283185307179586;
  constexpr double kHalfPi = 1.5707963267948966;
  if (hi - lo >= kTwoPi) return {-1.0f, 1.0f};
  float rlo = std::min(f(a.lo), f(a.hi)), rhi = std::max(f(a.lo), f(a.hi));
  rlo = std::max(-1.0f, down(rlo));
  rhi = std::min(1.0f, up(rhi));
  // Maxima at x + phase = pi/2 + 2k pi, minima at -pi/2 + 2k pi.
  auto hits = [&](double offset) {
    const double k = std::ceil((lo + phase - offset) / kTwoPi);
    return offset + k * kTwoPi - phase <= hi;
  };
  if (hits(kHalfPi)) rhi = 1.0f;
  if (hits(-kHalfPi)) rlo = -1.0f;
  return {rlo, rhi};
}

[[gnu::always_inline]] inline Interval op(Op op, Interval a, Interval b, Choice* choice) {
  *choice = Choice::Both;
  const bool ua = a.is_unknown();
  const bool ub = op_arity(op) == 2 && b.is_unknown();
  // and/or/not know what to do with a NaN argument; every other op propagates it.
  if (op != Op::And && op != Op::Or && op != Op::Not && (ua || ub)) return Interval::unknown();
  switch (op) {
    case Op::Neg:
      return {-a.hi, -a.lo};
    case Op::Abs:
      if (a.lo >= 0) return a;
      if (a.hi <= 0) return {-a.hi, -a.lo};
      return {0.0f, std::max(-a.lo, a.hi)};
    case Op::Recip:
      if (a.lo > 0 || a.hi < 0) return checked(1.0f / a.hi, 1.0f / a.lo);
      return {-kInf, kInf};
    case Op::Sqrt:
      if (a.lo < 0) return Interval::unknown();
      return {std::sqrt(a.lo), std::sqrt(a.hi)};
    case Op::Square:
      if (a.lo >= 0) return {a.lo * a.lo, a.hi * a.hi};
      if (a.hi <= 0) return {a.hi * a.hi, a.lo * a.lo};
      return {0.0f, std::max(a.lo * a.lo, a.hi * a.hi)};
    case Op::Floor:
      return {std::floor(a.lo), std::floor(a.hi)};
    case Op::Ceil:
      return {std::ceil(a.lo), std::ceil(a.hi)};
    case Op::Round:
      return {std::round(a.lo), std::round(a.hi)};
    case Op::Sin:
      return periodic(a, 0.0, [](float v) { return std::sin(v); });
    case Op::Cos:
      return periodic(a, 1.5707963267948966, [](float v) { return std::cos(v); });
    case Op::Tan: {
      if (!finite(a)) return Interval::unknown();
      constexpr double kPi = 3.141592653589793;
      const double k = std::ceil((static_cast<double>(a.lo) - kPi / 2) / kPi);
      if (kPi / 2 + k * kPi <= a.hi) return {-kInf, kInf};  // a pole inside
      return increasing(a, [](float v) { return std::tan(v); });
    }
    case Op::Asin:
      if (a.lo < -1.0f || a.hi > 1.0f) return Interval::unknown();
      return increasing(a, [](float v) { return std::asin(v); });
    case Op::Acos:
      if (a.lo < -1.0f || a.hi > 1.0f) return Interval::unknown();
      return decreasing(a, [](float v) { return std::acos(v); });
    case Op::Atan:
      return increasing(a, [](float v) { return std::atan(v); });
    case Op::Exp: {
      Interval r = increasing(a, [](float v) { return std::exp(v); });
      r.lo = std::max(r.lo, 0.0f);
      return r;
    }
    case Op::Ln:
      if (a.lo < 0) return Interval::unknown();
      return increasing(a, [](float v) { return std::log(v); });
    case Op::Not:
      if (ua) return {0.0f, 1.0f};
      if (!has_zero(a)) return {0.0f, 0.0f};
      if (a.lo == 0 && a.hi == 0) return {1.0f, 1.0f};
      return {0.0f, 1.0f};
    case Op::Add:
      if (add_may_nan(a, b)) return Interval::unknown();
      return checked(a.lo + b.lo, a.hi + b.hi);
    case Op::Sub:
      if (sub_may_nan(a, b)) return Interval::unknown();
      return checked(a.lo - b.hi, a.hi - b.lo);
    case Op::Mul: {
      if (mul_may_nan(a, b)) return Interval::unknown();
      const float p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
      if (std::isnan(p0) || std::isnan(p1) || std::isnan(p2) || std::isnan(p3)) return Interval::unknown();
      return {std::min(std::min(p0, p1), std::min(p2, p3)), std::max(std::max(p0, p1), std::max(p2, p3))};
    }
    case Op::Div: {
      if (b.lo > 0 || b.hi < 0) {
        if (!finite(a) && !finite(b)) return Interval::unknown();  // inf / inf
        const float q0 = a.lo / b.lo, q1 = a.lo / b.hi, q2 = a.hi / b.lo, q3 = a.hi / b.hi;
        if (std::isnan(q0) || std::isnan(q1) || std::isnan(q2) || std::isnan(q3)) return Interval::unknown();
        return {std::min(std::min(q0, q1), std::min(q2, q3)), std::max(std::max(q0, q1), std::max(q2, q3))};
      }
      if (has_zero(a)) return Interval::unknown();                // 0 / 0
      if (!finite(a) && !finite(b)) return Interval::unknown();  // inf / inf
      return {-kInf, kInf};
    }
    case Op::Atan2:
      return {down(-3.14159274f), up(3.14159274f)};
    case Op::Min:
      if (a.hi < b.lo) {
        *choice = Choice::Left;
        return a;
      }
      if (b.hi < a.lo) {
        *choice = Choice::Right;
        return b;
      }
      return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)};
    case Op::Max:
      if (a.lo > b.hi) {
        *choice = Choice::Left;
        return a;
      }
      if (b.lo > a.hi) {
        *choice = Choice::Right;
        return b;
      }
      return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)};
    case Op::Compare:
      if (a.hi < b.lo) return {-1.0f, -1.0f};
      if (a.lo > b.hi) return {1.0f, 1.0f};
      if (a.lo == a.hi && b.lo == b.hi && a.lo == b.lo) return {0.0f, 0.0f};
      return {a.hi <= b.lo ? -1.0f : (a.lo >= b.hi ? 0.0f : -1.0f), a.lo >= b.hi ? 1.0f : (a.hi <= b.lo ? 0.0f : 1.0f)};
    case Op::Mod: {
      if (!finite(a) || !finite(b) || has_zero(b)) return Interval::unknown();
      const float m = std::max(std::fabs(b.lo), std::fabs(b.hi));
      if (b.lo == b.hi) {
        const double period = std::fabs(static_cast<double>(b.lo));
        if (std::floor(a.lo / period) == std::floor(a.hi / period)) {
          const float rlo = op_mod(a.lo, b.lo), rhi = op_mod(a.hi, b.lo);
          if (rlo <= rhi) return {rlo, rhi};
        }
      }
      return {0.0f, m};
    }
    case Op::And:  // a == 0 ? a : b
      if (!ua && !has_zero(a)) {
        *choice = Choice::Right;
        return b;
      }
      if (!ua && a.lo == 0 && a.hi == 0) {
        *choice = Choice::Left;
        return a;
      }
      return hull({0.0f, 0.0f}, b);
    case Op::Or:  // a != 0 ? a : b
      if (ua) return Interval::unknown();  // a may be NaN, which `or` returns
      if (!has_zero(a)) {
        *choice = Choice::Left;
        return a;
      }
      if (a.lo == 0 && a.hi == 0) {
        *choice = Choice::Right;
        return b;
      }
      return hull(a, b);
    case Op::VarX:
    case Op::VarY:
    case Op::VarZ:
    case Op::Const:
    case Op::Oracle:
      break;
  }
  return Interval::unknown();
}

// The same, as an out-of-line call: for the rare ops and for callers that dispatch at run time.
[[gnu::noinline]] inline Interval op_generic(Op o, Interval a, Interval b, Choice* choice) { return op(o, a, b, choice); }

}  // namespace frep::ival
