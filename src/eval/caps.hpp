// Upper caps for simplification (private to the evaluation code), shared by single-box and
// 16-box simplification so both make the same choices. (The 16-box backward pass,
// SimplifyBackward in interval_batch.cpp, computes min_caps and upper in SIMD across its boxes:
// a change here must be made there too; the IntervalBatch tests compare the two tape for tape.)
//
// An instruction's cap C over a box says: the root does not change if the instruction's value is
// replaced by any value that equals it wherever it is <= C and stays > C wherever it is > C. The
// root's cap is +inf (its value must stay exact), or the root cap a consumer that reads less
// gives (Tape::simplify's root_cap; 0 where only signs are read). In min(a, b) with cap C, a matters only
// below min(C, hi(b)): above hi(b), b wins anyway. So a min side whose interval starts above its
// cap can go, although it may overlap its sibling: far terms of a big min tree are dropped
// against the nearest term anywhere in the tree, not only against their direct sibling. Max
// passes its cap to both sides; every other op gives its arguments +inf. A value used several
// times gets the largest of its caps. A min whose sides both start above its cap is above it
// throughout: one constant above the cap serves (it needs a finite cap: from the root cap, or
// from a sibling's upper bound through a max). A known interval holds no NaN, so nothing that
// can be NaN is ever dropped or replaced.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

#include "frep/eval/interval.hpp"

namespace frep::caps {

inline constexpr float kNone = std::numeric_limits<float>::infinity();

// An interval's upper bound as a cap: +inf if unknown.
inline float upper(float lo, float hi) { return lo <= hi ? hi : kNone; }

// min(a, b) under cap c, where the interval evaluation kept both sides: whether it is above the
// cap throughout (then `value` replaces it), else which side alone is enough (Choice::Both if
// neither), and the caps of the sides if both stay.
struct MinCaps {
  bool above = false;
  float value = 0;
  Choice choice = Choice::Both;
  float cap_a = kNone;
  float cap_b = kNone;
};

// The constant that replaces a min above its cap: the lower end of its interval, with a zero made
// +0 (the 16-box and single-box passes may disagree on the sign of a zero bound).
inline float above_value(float alo, float blo) {
  const float v = std::min(alo, blo);
  return v == 0.0f ? 0.0f : v;
}

inline MinCaps min_caps(float c, float alo, float ahi, float blo, float bhi) {
  MinCaps r;
  if (alo <= ahi && blo <= bhi && alo > c && blo > c) {
    r.above = true;
    r.value = above_value(alo, blo);
    return r;
  }
  r.cap_a = std::min(c, upper(blo, bhi));
  r.cap_b = std::min(c, upper(alo, ahi));
  // Comparisons with NaN (unknown intervals) are false: no choice.
  if (blo > r.cap_b) {
    r.choice = Choice::Left;
    r.cap_a = c;
  } else if (alo > r.cap_a) {
    r.choice = Choice::Right;
    r.cap_b = c;
  }
  return r;
}

// Whether a 16-box interval pass records a min's argument bounds for the caps: where some box to
// simplify (`lanes`) keeps both sides (`left`, `right`: the boxes where intervals chose one).
// Elsewhere no cap can change the choice. The pass and the simplification both ask this, so
// that they walk the same record.
inline bool min_bounds_recorded(std::uint32_t left, std::uint32_t right, std::uint32_t lanes) {
  return (~(left | right) & lanes) != 0;
}

}  // namespace frep::caps
