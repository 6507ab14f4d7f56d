// Bounds search: rounds of the subdivision driver over a cell grid, each keeping the boxes where
// the expression may be negative and zooming in on their bounding box.
#include "frep/contour/bounds.hpp"

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
        if (next.lo[a] <= grid.coords[a].front() || next.hi[a] >= grid.coords[a].back()) {
          char msg[400];
          std::snprintf(msg, sizeof msg,
                        "the expression may be negative as far as the search limit (+-%g) along %c: it looks "
                        "unbounded (a half-space, a 2D shape, a lattice...); give the region with "
                        "--bounds x0,y0,z0,x1,y1,z1",
                        o.limit, "xyz"[a]);
          throw InputError("", 0, msg);
        }
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
