// Bounds search: rounds of the subdivision driver over a cell grid, each keeping the boxes where
// the expression may be negative and zooming in on their bounding box.
#include "frep/contour/bounds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"

namespace frep {
namespace {

std::vector<int> tiles_for(int cells) {
  std::vector<int> t{1};
  while (t.front() * 4 < cells) t.insert(t.begin(), t.front() * 4);
  return t;
}

// Why the interval search could not bound the inside, told from samples on nested cubes
// (+-limit down to +-1, 32^3 points each, so that a shape a few units across is seen whatever the
// limit): NaN everywhere, negative far out (unbounded), or negative only near the origin
// (bounded, but intervals too wide to prove it), with the region to give.
std::string unproven_bound_message(const Tape& tape, double limit, int axis) {
  PointEvaluator pe;
  Box3 negative;
  std::uint64_t samples = 0, nan = 0;
  constexpr int kSide = 32;
  for (double r = limit; r >= 0.999; r /= 10)
    for (int i = 0; i < kSide; ++i)
      for (int j = 0; j < kSide; ++j)
        for (int k = 0; k < kSide; ++k) {
          // Cell centres, so that no sample sits on a symmetry plane through the origin.
          const Vec3 p{-r + 2 * r * (i + 0.5) / kSide, -r + 2 * r * (j + 0.5) / kSide, -r + 2 * r * (k + 0.5) / kSide};
          const float v = pe.eval(tape, static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
          ++samples;
          if (std::isnan(v)) ++nan;
          else if (v < 0) negative.add(p);
        }
  char msg[700];
  if (nan == samples) {
    std::snprintf(msg, sizeof msg,
                  "the expression is NaN (undefined) at every one of %llu points sampled within +-%g: there is no "
                  "inside to find",
                  static_cast<unsigned long long>(samples), limit);
    return msg;
  }
  const double reach = std::max({std::fabs(negative.lo.x), std::fabs(negative.lo.y), std::fabs(negative.lo.z),
                                 std::fabs(negative.hi.x), std::fabs(negative.hi.y), std::fabs(negative.hi.z)});
  // The finest sampled cube holding every negative sample: negatives in its outer layer of
  // samples may go on beyond it (a thin cylinder is missed by the coarser cubes' samples).
  double cube = limit;
  while (cube / 10 >= 0.999 && cube / 10 >= reach) cube /= 10;
  const double spacing = 2 * cube / kSide;
  if (!negative.empty() && (reach > 0.5 * limit || reach > cube - 1.5 * spacing)) {
    std::snprintf(msg, sizeof msg,
                  "the expression is negative as far as %g from the origin among the points sampled, and may go on "
                  "beyond (the search limit is +-%g): it looks unbounded (a half-space, a 2D shape, a lattice...); "
                  "give the region with --bounds x0,y0,z0,x1,y1,z1",
                  reach, limit);
    return msg;
  }
  if (negative.empty()) {
    std::snprintf(msg, sizeof msg,
                  "interval arithmetic could not prove where the expression is negative (it may be, as far as "
                  "+-%g along %c), and no point sampled within that is negative: the shape is thin or empty; give "
                  "the region with --bounds x0,y0,z0,x1,y1,z1",
                  limit, "xyz"[axis]);
    return msg;
  }
  // Grown by the sample spacing (the surface may lie up to a spacing beyond the last negative
  // sample), and a tenth more.
  const Vec3 size = negative.size();
  const double pad = 0.1 * std::max({size.x, size.y, size.z}) + spacing;
  const Box3 b = negative.inflated(pad);
  std::snprintf(msg, sizeof msg,
                "interval arithmetic could not prove a bound (its intervals far from the origin cover both signs, "
                "as far as +-%g along %c), but every negative point among %llu sampled lies within %.3g, %.3g, "
                "%.3g .. %.3g, %.3g, %.3g: if that is the shape, give --bounds %.3g,%.3g,%.3g,%.3g,%.3g,%.3g",
                limit, "xyz"[axis], static_cast<unsigned long long>(samples), negative.lo.x, negative.lo.y,
                negative.lo.z, negative.hi.x, negative.hi.y, negative.hi.z, b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y,
                b.hi.z);
  return msg;
}

}  // namespace

BoundsResult find_bounds(const Tape& tape, const BoundsSearchOptions& o) {
  if (!(o.limit > 0) || !std::isfinite(o.limit) || o.limit > 1e30)
    throw InputError("", 0, "the bounds search limit must be a positive finite number");
  if (o.cells < 2 || o.cells > 1024) throw InputError("", 0, "the bounds search needs 2 to 1024 cells per axis");
  SubdivisionOptions so;
  so.tiles = tiles_for(o.cells);
  so.threads = o.threads;
  so.lipschitz = o.lipschitz;
  Subdivider sub(so);

  // Keeps the bounding box of the boxes that may be negative, per worker. A box inside the
  // worker's box so far cannot change the result, so it is skipped unevaluated: only boxes at
  // the frontier of the box found are refined (the union over workers does not depend on the
  // order boxes come in).
  struct Visitor {
    static constexpr bool leaf_tape() { return false; }
    const SampleGrid& grid;
    std::vector<Box3>& found;  // per worker
    bool skip(int wi, const IndexBox& b) {
      const Box3& f = found[static_cast<std::size_t>(wi)];
      for (int a = 0; a < 3; ++a) {
        const Interval r = grid.range(a, b.lo[a], b.hi[a]);
        if (r.lo < f.lo[a] || r.hi > f.hi[a]) return false;
      }
      return true;
    }
    void keep(int wi, const IndexBox& b) {
      Box3& f = found[static_cast<std::size_t>(wi)];
      for (int a = 0; a < 3; ++a) {
        const Interval r = grid.range(a, b.lo[a], b.hi[a]);
        f.lo[a] = std::min(f.lo[a], static_cast<double>(r.lo));
        f.hi[a] = std::max(f.hi[a], static_cast<double>(r.hi));
      }
    }
    bool settled(int wi, const IndexBox& b, Interval v) {
      if (v.is_unknown()) return false;
      if (v.lo >= 0) return true;  // nowhere negative
      if (v.hi < 0) return keep(wi, b), true;
      return false;
    }
    void leaf(int wi, const Tape&, const IndexBox& b) { keep(wi, b); }
  };

  BoundsResult res;
  Box3 box{{-o.limit, -o.limit, -o.limit}, {o.limit, o.limit, o.limit}};
  for (int round = 0; round < o.max_rounds; ++round) {
    SampleGrid grid;
    grid.cells = true;
    for (int a = 0; a < 3; ++a) {
      auto& c = grid.coords[static_cast<std::size_t>(a)];
      c.resize(static_cast<std::size_t>(o.cells) + 1);
      for (int i = 0; i <= o.cells; ++i) {
        // Rounded outwards at the ends, so the float grid covers the double box.
        const double x = box.lo[a] + (box.hi[a] - box.lo[a]) * i / o.cells;
        float fx = static_cast<float>(x);
        if (i == 0 && fx > x) fx = std::nextafter(fx, -INFINITY);
        if (i == o.cells && fx < x) fx = std::nextafter(fx, INFINITY);
        c[static_cast<std::size_t>(i)] = fx;
      }
    }
    std::vector<Box3> found(static_cast<std::size_t>(sub.workers()));
    Visitor v{grid, found};
    sub.run(tape, grid, v);
    Box3 next;
    for (const Box3& f : found) next.add(f);
    res.rounds = round + 1;
    if (next.empty()) {
      if (round == 0) {
        res.empty = true;
        return res;
      }
      break;  // cannot happen (the previous round found something inside this box); keep it
    }
    if (round == 0) {
      for (int a = 0; a < 3; ++a)
        if (next.lo[a] <= grid.coords[a].front() || next.hi[a] >= grid.coords[a].back())
          throw InputError("", 0, unproven_bound_message(tape, o.limit, a));
    }
    double moved = 0;
    for (int a = 0; a < 3; ++a) {
      const double ext = box.hi[a] - box.lo[a];
      moved = std::max(moved, std::max(next.lo[a] - box.lo[a], box.hi[a] - next.hi[a]) / ext);
    }
    box = next;
    if (moved <= o.converged) break;
  }
  res.box = box;
  return res;
}

Box3 field_region(const Tape& tape, const FieldInfo& info, const BoundsSearchOptions& options) {
  // A converted mesh's box is known; the interval search on big converted meshes takes far longer.
  if (!info.bounds.empty()) return info.bounds;
  BoundsSearchOptions o = options;
  if (!(o.lipschitz > 0)) o.lipschitz = info.lipschitz;
  const BoundsResult b = find_bounds(tape, o);
  if (b.empty) throw InputError("", 0, "the field is not negative anywhere: the solid is empty, there is nothing to work on");
  return b.box;
}

Box3 checked_bounds(const Tape& result, const Box3& grown) {
  if (grown.empty()) return {};
  // 0.3% beyond: a converted mesh's own box bound (see convert) sits 0.1% outside its triangles.
  const Box3 box = grown.inflated(0.003 * length(grown.size()));
  IntervalEvaluator ie;
  for (int axis = 0; axis < 3; ++axis)
    for (const double at : {box.lo[axis], box.hi[axis]}) {
      Interval iv[3];
      for (int a = 0; a < 3; ++a) iv[a] = a == axis ? Interval{static_cast<float>(at), static_cast<float>(at)}
                                                   : Interval{static_cast<float>(box.lo[a]), static_cast<float>(box.hi[a])};
      const Interval r = ie.eval(result, iv[0], iv[1], iv[2]);
      if (!(r.lo > 0)) return {};
    }
  return box;
}

}  // namespace frep
