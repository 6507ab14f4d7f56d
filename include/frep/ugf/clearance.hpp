// Measuring the clearance between two bodies: the minimum of S = A + B (two_body.hpp) over a
// region, by interval branch and bound with a local polish (UGF.md, "Two-body field and
// clearance").
#pragma once

#include <cstddef>

#include "frep/eval/interval.hpp"
#include "frep/expr/expr.hpp"

namespace frep::ugf {

struct ClearanceOptions {
  // Stop when the best value found is within this of the proven lower bound.
  float tolerance = 1e-4f;
  // Most boxes to examine; on reaching it the lower bound is whatever was proven.
  std::size_t max_boxes = 200000;
};

struct ClearanceResult {
  // The smallest S found (at x, y, z): the gap if > 0, minus the interference depth if < 0.
  float value = 0;
  // A proven lower bound on S over the region (from interval arithmetic, so <= value). When
  // value - lower_bound <= tolerance, `value` is the minimum to within the tolerance.
  float lower_bound = 0;
  float x = 0, y = 0, z = 0;
  std::size_t boxes = 0;  // boxes examined
};

// Minimizes A + B over the box [x] x [y] x [z]. A and B should be signed distances (or UGFs);
// for other fields the minimum of A + B is not a gap.
ClearanceResult find_clearance(Expr A, Expr B, Interval x, Interval y, Interval z,
                               const ClearanceOptions& opt = {});

}  // namespace frep::ugf
