// Closed f32 intervals. Bounds are computed so that for every f32 point inside the argument
// intervals, the point evaluator's f32 result lies inside the result interval (monotone ops use
// the same f32 operations on the bounds; libm functions are widened by two ulps).
// An interval whose bounds are NaN means "unknown": the value may be anything, NaN included.
#pragma once

#include <cstdint>
#include <limits>

#include "frep/expr/opcode.hpp"

namespace frep {

struct Interval {
  float lo = 0;
  float hi = 0;

  static Interval unknown() {
    return {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN()};
  }
  static Interval point(float v) { return {v, v}; }
  bool is_unknown() const { return !(lo <= hi); }
  // True if point value `v` is inside (an unknown interval contains everything, NaN included).
  bool contains(float v) const { return is_unknown() || (v >= lo && v <= hi); }
};

// Which side of a min/max/and/or won over a whole region.
enum class Choice : std::uint8_t {
  Both = 0,   // either side may win somewhere: keep both
  Left = 1,   // the result is always the first argument
  Right = 2,  // the result is always the second argument
};

// Evaluates one op on intervals; writes the choice for min/max/and/or (Both otherwise).
Interval interval_op(Op op, Interval a, Interval b, Choice* choice);

}  // namespace frep
