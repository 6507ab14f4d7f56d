// Closed f32 intervals. Bounds are computed so that for every f32 point inside the argument
// intervals, the point evaluator's f32 result lies inside the result interval (monotone ops use
// the same f32 operations on the bounds; libm functions are widened by two ulps).
// An interval whose bounds are NaN means "unknown": the value may be anything, NaN included.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

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

// A box's centre as the evaluators see it (0.5 lo + 0.5 hi in float, so that its rounding is
// the same wherever it is computed), its half-diagonal measured from that rounded centre (so
// that the rounding is covered), and its largest coordinate magnitude: what lipschitz_bound takes.
struct BoxCentre {
  float c[3] = {0, 0, 0};
  double half_diagonal = 0;
  double scale = 0;
};
inline BoxCentre box_centre(Interval x, Interval y, Interval z) {
  BoxCentre b;
  const Interval* axes[3] = {&x, &y, &z};
  double r2 = 0;
  for (int a = 0; a < 3; ++a) {
    const Interval& r = *axes[a];
    b.c[a] = 0.5f * r.lo + 0.5f * r.hi;
    const double e = std::max(static_cast<double>(b.c[a]) - r.lo, static_cast<double>(r.hi) - b.c[a]);
    r2 += e * e;
    b.scale = std::max({b.scale, std::fabs(static_cast<double>(r.lo)), std::fabs(static_cast<double>(r.hi))});
  }
  b.half_diagonal = std::sqrt(r2);
  return b;
}

// The interval of a box, narrowed by a Lipschitz bound: every value of f in a box with centre c
// and half-diagonal r lies within f(c) +- L r. `centre` is the interval evaluation of the
// centre (a box of one point), so it contains the computed f(c); the radius is grown by 2^-16 of
// itself and of the magnitudes involved, which covers the float rounding of a field that is
// L-Lipschitz in exact arithmetic (converted meshes are exact to about 2^-22 of their size).
// Unknown (NaN) intervals stay as they are.
inline Interval lipschitz_bound(Interval box, Interval centre, double lipschitz, double half_diagonal, double coord_scale) {
  if (box.is_unknown() || centre.is_unknown() || !(lipschitz > 0)) return box;
  const double mag = std::max(std::fabs(static_cast<double>(centre.lo)), std::fabs(static_cast<double>(centre.hi)));
  const double r = lipschitz * half_diagonal * (1 + 0x1p-16) + 0x1p-16 * (mag + coord_scale);
  // Rounded outward to float, so that the narrowed interval still contains every value.
  float lo = static_cast<float>(centre.lo - r), hi = static_cast<float>(centre.hi + r);
  if (static_cast<double>(lo) > centre.lo - r) lo = std::nextafter(lo, -INFINITY);
  if (static_cast<double>(hi) < centre.hi + r) hi = std::nextafter(hi, INFINITY);
  const Interval out{std::max(box.lo, lo), std::min(box.hi, hi)};
  return out.is_unknown() ? box : out;  // disjoint only if f is not L-Lipschitz: keep what intervals proved
}

}  // namespace frep
