// The rules by which modeling operations carry a field's facts.
#include "frep/model/field.hpp"

#include <algorithm>
#include <cmath>

namespace frep {
namespace {

// A bound of both operands' (unknown if either is).
double larger_bound(double a, double b) { return a > 0 && b > 0 ? std::max(a, b) : 0.0; }

Growth weaker(Growth a, Growth b) { return static_cast<Growth>(std::min(static_cast<int>(a), static_cast<int>(b))); }

// Growth never outlives the box it is about.
FieldInfo settled(FieldInfo f) {
  if (f.bounds.empty()) f.growth = Growth::Unknown;
  return f;
}

}  // namespace

Field field_of(const Model& m) { return Field(m.root_expr(), m.info); }

FieldInfo union_info(const FieldInfo& a, const FieldInfo& b) {
  FieldInfo r;
  r.lipschitz = larger_bound(a.lipschitz, b.lipschitz);
  if (!a.bounds.empty() && !b.bounds.empty()) {
    r.bounds = a.bounds;
    r.bounds.add(b.bounds);
    // min(a, b) < t where a < t or b < t; and min(a, b)(p) >= the distance to the union when
    // both are at least their own distances.
    r.growth = weaker(a.growth, b.growth);
  }
  return settled(r);
}

FieldInfo intersection_info(const FieldInfo& a, const FieldInfo& b) {
  FieldInfo r;
  r.lipschitz = larger_bound(a.lipschitz, b.lipschitz);
  if (a.bounds.empty() && b.bounds.empty()) return r;
  Box3 box;
  if (a.bounds.empty() || b.bounds.empty()) {
    box = a.bounds.empty() ? b.bounds : a.bounds;
    r.growth = std::min(a.bounds.empty() ? b.growth : a.growth, Growth::Box);
  } else {
    box = {max(a.bounds.lo, b.bounds.lo), min(a.bounds.hi, b.bounds.hi)};
    // max(a, b) < t within both grown boxes, which meet in the common box grown by t (per axis);
    // not Distance: a wedge's max underestimates the distance to its edge.
    r.growth = std::min(weaker(a.growth, b.growth), Growth::Box);
  }
  // Disjoint boxes: an empty inside, which FieldInfo cannot say; leave the box unknown.
  if (!box.empty()) r.bounds = box;
  return settled(r);
}

FieldInfo difference_info(const FieldInfo& a, const FieldInfo& b) {
  FieldInfo r;
  r.lipschitz = larger_bound(a.lipschitz, b.lipschitz);
  r.bounds = a.bounds;  // max(a, -b) >= a
  r.growth = std::min(a.growth, Growth::Box);
  return settled(r);
}

FieldInfo inverse_info(const FieldInfo& a) {
  FieldInfo r;
  r.lipschitz = a.lipschitz;
  return r;
}

FieldInfo offset_info(const FieldInfo& a, double r) {
  FieldInfo o;
  o.lipschitz = a.lipschitz;
  if (a.bounds.empty() || !std::isfinite(r)) return o;
  if (r <= 0) {
    // Shrunk: the inside is within the old one, and f - r < t where f < t - r <= t. Not Distance:
    // a thin part vanishes, and then the nearest inside point is farther than f says.
    o.bounds = a.bounds;
    o.growth = std::min(a.growth, Growth::Box);
  } else if (a.growth != Growth::Unknown) {
    // f - r < t where f < t + r, within the box grown by t + r; f - r stays at least the
    // distance to the grown inside when f was at least the distance to the old one.
    o.bounds = a.bounds.inflated(r);
    o.growth = a.growth;
  }
  return settled(o);
}

FieldInfo union_within_info(const FieldInfo& a, const FieldInfo& b, double reach, double lipschitz) {
  FieldInfo r;
  r.lipschitz = lipschitz;
  const FieldInfo u = union_info(a, b);
  if (u.growth != Growth::Unknown && reach >= 0 && std::isfinite(reach)) {
    // g < t where min(a, b) < t + reach.
    r.bounds = u.bounds.inflated(reach);
    r.growth = Growth::Box;
  }
  return settled(r);
}

FieldInfo affine_info(const FieldInfo& a, const Affine3& m) {
  FieldInfo r;
  if (a.lipschitz > 0 && m.finite()) r.lipschitz = a.lipschitz * m.stretch_bound();
  const auto inv = m.inverse();
  if (a.bounds.empty() || !inv) return settled(r);
  // The inside of f(m(p)) is m^-1 of f's: within the box of the eight corners mapped back.
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{(c & 1) ? a.bounds.hi.x : a.bounds.lo.x, (c & 2) ? a.bounds.hi.y : a.bounds.lo.y,
                      (c & 4) ? a.bounds.hi.z : a.bounds.lo.z};
    r.bounds.add(inv->apply(corner));
  }
  // Rounding of the corners above: widen by a relative hair so the box still holds the inside.
  const Vec3 size = r.bounds.size();
  r.bounds = r.bounds.inflated(1e-12 * (std::fabs(size.x) + std::fabs(size.y) + std::fabs(size.z)) +
                               1e-15 * (std::fabs(r.bounds.lo.x) + std::fabs(r.bounds.hi.x) + std::fabs(r.bounds.lo.y) +
                                        std::fabs(r.bounds.hi.y) + std::fabs(r.bounds.lo.z) + std::fabs(r.bounds.hi.z)));
  if (!std::isfinite(r.bounds.lo.x + r.bounds.lo.y + r.bounds.lo.z + r.bounds.hi.x + r.bounds.hi.y + r.bounds.hi.z)) {
    r.bounds = {};
    return settled(r);
  }
  // Distance survives a map m that never shrinks distances (|m^-1| <= 1: the shape is moved,
  // turned, mirrored or made smaller): f(m p) >= d(m p, S) >= d(p, m^-1 S). Box survives when
  // m^-1 maps the cube of half-width t into one of half-width t (rows of |m^-1| summing to at
  // most 1), as translations, mirrors, axis swaps and shrinking scales do.
  constexpr double kHair = 1 + 1e-9;
  double row_sum = 0;
  for (const auto& row : inv->m) row_sum = std::max(row_sum, std::fabs(row[0]) + std::fabs(row[1]) + std::fabs(row[2]));
  if (a.growth == Growth::Distance && inv->stretch_bound() <= kHair) r.growth = Growth::Distance;
  else if (a.growth != Growth::Unknown && row_sum <= kHair) r.growth = Growth::Box;
  return settled(r);
}

}  // namespace frep
