// Measuring the clearance between two bodies: the minimum of S = A + B (two_body.hpp) over a
// region, by interval branch and bound with a local polish (docs/ugf.md, "Two bodies
// and clearance"); then where the bodies are nearest, or the deepest point they share.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "frep/eval/interval.hpp"
#include "frep/expr/expr.hpp"
#include "frep/math/vec.hpp"

namespace frep {
class Tape;
}

namespace frep::ugf {

// Where a running search is (ClearanceOptions::progress).
struct ClearanceProgress {
  std::size_t boxes = 0;  // boxes examined so far
  float value = 0;        // the smallest S found so far
  float lower_bound = 0;  // what is proven so far: S >= this over the region
};

struct ClearanceOptions {
  // Stop when the best value found is within this of the proven lower bound.
  float tolerance = 1e-4f;
  // Most boxes to examine; on reaching it the lower bound is whatever was proven.
  std::size_t max_boxes = 200000;
  // A bound L on |S(p) - S(q)| / |p - q| (2 for two signed distances), or 0 if unknown. When
  // given, a box's lower bound is S at its centre minus L times its reach, from one evaluation
  // of A and of B there (also the box's sample), instead of interval arithmetic on S and a
  // separate sample: half the work where that is the interval bound anyway (mesh leaves), and no
  // tape per box (so no pruning of big expressions: leave 0 for those). The bound allows for A
  // and B being exact up to their rounding to float, as mesh leaves in place are; leave 0 for
  // fields less exact than that (converted closed forms, exact to about 2^-22 of their size;
  // moved mesh leaves, which round the moved point to float).
  double lipschitz = 0;
  // Points where S is sampled before the search (where the bodies are known to meet, say): a
  // good first value lets the search discard more boxes.
  std::vector<Vec3f> seeds;
  // Called every 16 boxes (from the calling thread); returning false stops the search there,
  // with the result proven so far.
  std::function<bool(const ClearanceProgress&)> progress;
};

struct ClearanceResult {
  // The smallest S found (at x, y, z): the gap if > 0, minus the interference depth if < 0.
  float value = 0;
  // A proven lower bound on S over the region (from interval arithmetic, so <= value). When
  // value - lower_bound <= tolerance, `value` is the minimum to within the tolerance.
  float lower_bound = 0;
  float x = 0, y = 0, z = 0;
  std::size_t boxes = 0;  // boxes examined
  bool stopped = false;   // the progress callback stopped the search
  // The search ended because nothing left could be below value - tolerance (not for lack of
  // boxes, nor stopped). Then lower_bound is within the tolerance of value, unless cells too
  // small to split in float were set aside (their bound is in lower_bound).
  bool converged = false;

  // Whether `value` is proven the minimum to within `tolerance` (ClearanceOptions::tolerance
  // before its rounding to float): converged, with lower_bound that close, allowing for the
  // search having compared them in float.
  bool within_tolerance(double tolerance) const;
};

// Minimizes A + B over the box [x] x [y] x [z]. A and B should be signed distances (or UGFs);
// for other fields the minimum of A + B is not a gap.
ClearanceResult find_clearance(Expr A, Expr B, Interval x, Interval y, Interval z,
                               const ClearanceOptions& opt = {});

// Where the volume two bodies share lies, from their bounding boxes: the boxes' intersection,
// padded by a thousandth of its diagonal so that points on its faces (where the surfaces touch)
// stay inside once the region is rounded to float.
Box3 shared_region(const Box3& a, const Box3& b);

// The point of f's surface nearest p, for a signed distance f: p - f(p) grad f / |grad f| (exact
// for planes and spheres). p itself where the gradient is zero or not finite. For a gap (a
// minimum of A + B >= 0 at p), the nearest points are p projected onto A and onto B.
Vec3 project_to_surface(const Tape& f, const Vec3f& p);

// Where two bodies interfere most (deepest_point).
struct DeepestPoint {
  Vec3 point;
  // `point` is inside both bodies (both fields negative there, evaluated in float). False when no
  // such point was found: `point` is then the point given.
  bool inside_both = false;
};

// A point inside both bodies A and B (signed distances) from a minimizer p of A + B < 0, as
// find_clearance returns it. That sum is constant along the whole deepest segment, so p may lie
// anywhere on it, even outside one body: moving along A's gradient by (B - A) / 2 evens the two
// depths (exact for signed distances). Falls back on the middle of the two surface points
// nearest p (project_to_surface), then on p itself.
DeepestPoint deepest_point(const Tape& a, const Tape& b, const Vec3f& p);

}  // namespace frep::ugf
