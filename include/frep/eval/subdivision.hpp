// The subdivision driver shared by everything that walks space with interval pruning: the 2D
// and 3D renderers, the octree mesher and dense sampling. It splits a box of grid samples into
// tiles, level by level; at each level up to 16 child boxes go through one SIMD interval pass
// (IntervalBatchEvaluator) and one shared simplification pass, so that deep boxes evaluate only
// their local part of the expression. The caller decides, per box, whether its interval settles
// it (an image tile fully inside, an empty octree cell), and receives the undecided boxes of the
// last level with their simplified tape.
//
// Work is spread over a persistent pool: the first levels are expanded breadth first, then each
// box of that frontier is finished depth first by one worker, with per-worker scratch (tapes per
// level). Every box is visited exactly once, so output written per box does not depend on the
// thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "frep/error.hpp"
#include "frep/eval/interval.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/eval/tape.hpp"
#include "frep/util/thread_pool.hpp"

namespace frep {

// A box of grid indices: [lo[a], hi[a]) along each axis a (x, y, z).
struct IndexBox {
  std::array<int, 3> lo{0, 0, 0}, hi{0, 0, 0};
  int extent(int axis) const { return hi[axis] - lo[axis]; }
  long long count() const { return static_cast<long long>(extent(0)) * extent(1) * extent(2); }
};

// Where the grid indices are in space. Each axis lists coordinates, increasing or decreasing
// (an image's rows run from +y down). Samples: index i is the point coords[i], and a box covers
// the samples lo..hi-1. Cells: index i is the closed cell [coords[i], coords[i+1]] (coords has
// one more entry than there are cells), and a box covers lo..hi inclusive.
struct SampleGrid {
  std::array<std::vector<float>, 3> coords;
  bool cells = false;

  // Number of samples or cells along an axis.
  int count(int axis) const {
    const int n = static_cast<int>(coords[axis].size());
    return cells ? std::max(0, n - 1) : n;
  }
  IndexBox whole() const { return {{0, 0, 0}, {count(0), count(1), count(2)}}; }
  // Throws InputError (naming `what`, the region's use) unless every coordinate is a finite
  // float (a region beyond 32-bit floats would be evaluated at infinities) and each axis's
  // coordinates are distinct when it has more than two (samples rounded to one float would all
  // get one value; two equal coordinates make a plane of cells, as slices use).
  void check(const char* what) const;
  // The coordinate range a box covers along an axis.
  Interval range(int axis, int lo, int hi) const {
    const float a = coords[axis][lo], b = coords[axis][cells ? hi : hi - 1];
    return {std::min(a, b), std::max(a, b)};
  }
};

struct SubdivisionOptions {
  std::vector<int> tiles = {256, 64, 16};  // box edge per level in grid steps, largest first
  int threads = 0;                         // worker threads; 0 = all hardware threads
  int breadth_first_levels = 2;            // levels expanded breadth first to make parallel work; 0: none,
                                           // boxes of the first level with at least 4 per worker run in parallel,
                                           // each from the whole tape (least memory; always so for tapes of 2^18
                                           // instructions and more)
  double lipschitz = 0;                    // L with |f(p) - f(q)| <= L |p - q| in the grid's coordinates (1 for exact
                                           // distances), or 0 if unknown: boxes then also settle from their centre's
                                           // value, f(c) +- L * half-diagonal (see lipschitz_bound)
  float value_cap = kExactValues;          // C: the visitor needs values exactly only where they are <= C, elsewhere
                                           // only that they are > C (0 for inside/outside images). Tapes are then
                                           // simplified with root cap C (Tape::simplify), much shorter ones for
                                           // signs; intervals still settle boxes against C rightly. Not used with
                                           // a Lipschitz bound (a centre's value above C is not the expression's)
};

// Reusable: keeps the pool, per-worker evaluators and tape storage between runs.
//
// The visitor provides
//   bool settled(int worker, const IndexBox& box, Interval value)
//       after the box's interval evaluation; return true if the value settles the box (the
//       driver then neither subdivides it nor passes it to leaf()).
//   void leaf(int worker, const Tape& tape, const IndexBox& box)
//       for every box of the last level that was not settled; `tape` is simplified for it and
//       has register code (for the point, batch and gradient evaluators).
// and optionally
//   bool skip(int worker, const IndexBox& box)
//       before a box is evaluated; return true to drop it (e.g. occluded in a 3D render).
//   static constexpr bool leaf_tape() { return false; }
//       leaf() does not use its tape: the last level is then not simplified, and leaf() gets
//       the parent's tape (valid in the box).
// Visitor calls for different boxes may run concurrently on different workers.
class Subdivider {
 public:
  explicit Subdivider(SubdivisionOptions options = {});
  ~Subdivider();
  Subdivider(const Subdivider&) = delete;
  Subdivider& operator=(const Subdivider&) = delete;

  const SubdivisionOptions& options() const { return options_; }
  // Number of workers: worker indices passed to the visitor are below this.
  int workers() const { return pool_->size(); }
  // The pool, for the caller's own parallel loops between runs (not during one).
  ThreadPool& pool() { return *pool_; }

  // Subdivides `region` of `grid` (by default all of it) with `tape`.
  template <class Visitor>
  void run(const Tape& tape, const SampleGrid& grid, Visitor& visitor) {
    run(tape, grid, grid.whole(), visitor);
  }
  template <class Visitor>
  void run(const Tape& tape, const SampleGrid& grid, const IndexBox& region, Visitor& visitor);

 private:
  static constexpr int kLanes = IntervalBatchEvaluator::kLanes;
  // Tapes from this size on are big: a child keeping nearly all of one uses it instead of a
  // copy, and groups hold fewer boxes, so that a level keeps at most about kGroupInstructions
  // instructions of children's tapes at once (not 16 copies of a multi-million-node tape).
  static constexpr std::size_t kBigTape = std::size_t{1} << 18;
  static constexpr std::size_t kGroupInstructions = std::size_t{1} << 26;
  // A child of a big tape keeping more than this fraction of it uses the parent's tape.
  static constexpr double kMaxKept = 0.625;
  // Boxes per interval pass: fewer on big tapes (memory), and at most half the lanes with a
  // Lipschitz bound (the other half evaluates the boxes' centres in the same pass).
  int group_lanes(const Tape& t) const {
    const int lanes = options_.lipschitz > 0 ? kLanes / 2 : kLanes;
    return static_cast<int>(std::clamp<std::size_t>(kGroupInstructions / std::max<std::size_t>(t.size(), 1), 1, lanes));
  }
  // Instructions' worth of big children's buffers a worker keeps for the next big children, so
  // that they are written into memory already mapped (fresh pages cost the kernel a page clear).
  static constexpr std::size_t kSpareInstructions = std::size_t{1} << 23;
  struct Worker {
    IntervalBatchEvaluator boxes;
    std::vector<std::array<Tape, kLanes>> tapes;  // per level: the current group's children
    std::vector<Tape> spare;                      // released big children, for their buffers
    std::size_t spare_size = 0;                   // their capacity in instructions
  };
  struct Item {
    IndexBox box;
    const Tape* tape;  // valid inside box
  };

  // Evaluates `count` boxes of one level on `t` (valid in all of them) in one interval pass,
  // simplifies `t` for those not settled into dst[k], and passes each to next(child). With
  // `release`, next() is done with a child when it returns, and big children's tapes go back.
  template <class Visitor, class Next>
  void settle(Worker& w, const Tape& t, const SampleGrid& grid, bool last, const IndexBox* boxes, int count,
              Visitor& v, int worker, Tape* dst, Next&& next, bool release = true);
  // Calls f(child) for each box of edge `step` (the last ones cut at the parent's end) that
  // splits `parent`: x fastest, then y, then z.
  template <class F>
  static void for_each_child(const IndexBox& parent, int step, F&& f) {
    for (int z = parent.lo[2]; z < parent.hi[2]; z += step)
      for (int y = parent.lo[1]; y < parent.hi[1]; y += step)
        for (int x = parent.lo[0]; x < parent.hi[0]; x += step)
          f(IndexBox{{x, y, z},
                     {std::min(x + step, parent.hi[0]), std::min(y + step, parent.hi[1]), std::min(z + step, parent.hi[2])}});
  }
  // Splits `parent` (valid tape `t`) into boxes of level `level`, 16 at a time: one interval pass
  // settles them or not, one shared pass simplifies `t` for the others into outs(group), and
  // next(child) receives each unsettled child.
  template <class Visitor, class Outs, class Next>
  void split(Worker& w, const Tape& t, const SampleGrid& grid, int level, const IndexBox& parent, Visitor& v,
             int worker, Outs&& outs, Next&& next);

  // One breadth-first level from a frontier of fewer boxes than workers: their children in
  // groups of at most group_lanes, enough groups for every worker, settled in parallel. Returns
  // the children left open (in the order split() would give), or visits them if they are leaves.
  template <class Visitor>
  std::vector<Item> split_among_workers(const std::vector<Item>& frontier, const SampleGrid& grid, int level,
                                        int levels, Visitor& v, std::vector<Tape>& store);

  SubdivisionOptions options_;
  std::unique_ptr<ThreadPool> pool_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::vector<std::vector<Tape>> frontier_tapes_;  // simplified tapes of the breadth-first levels
};

// ---------------------------------------------------------------------------------------------
// Implementation (a template: the visitor's calls inline into the loops).

template <class Visitor, class Next>
void Subdivider::settle(Worker& w, const Tape& t, const SampleGrid& grid, bool last, const IndexBox* boxes, int count,
                        Visitor& v, int worker, Tape* dst, Next&& next, bool release) {
  Interval xi[kLanes], yi[kLanes], zi[kLanes];
  for (int k = 0; k < count; ++k) {
    xi[k] = grid.range(0, boxes[k].lo[0], boxes[k].hi[0]);
    yi[k] = grid.range(1, boxes[k].lo[1], boxes[k].hi[1]);
    zi[k] = grid.range(2, boxes[k].lo[2], boxes[k].hi[2]);
  }
  // With a Lipschitz bound, lanes count..2 count - 1 hold the boxes' centres.
  const bool centres = options_.lipschitz > 0 && 2 * count <= kLanes;
  double radius[kLanes], scale[kLanes];  // half-diagonal, largest coordinate magnitude
  if (centres)
    for (int k = 0; k < count; ++k) {
      const BoxCentre b = box_centre(xi[k], yi[k], zi[k]);
      xi[count + k] = Interval::point(b.c[0]);
      yi[count + k] = Interval::point(b.c[1]);
      zi[count + k] = Interval::point(b.c[2]);
      radius[k] = b.half_diagonal;
      scale[k] = b.scale;
    }
  w.boxes.eval(t, xi, yi, zi, centres ? 2 * count : count, count);
  std::uint32_t open = 0;
  for (int k = 0; k < count; ++k) {
    Interval value = w.boxes.result(k);
    if (centres) value = lipschitz_bound(value, w.boxes.result(count + k), options_.lipschitz, radius[k], scale[k]);
    if (!v.settled(worker, boxes[k], value)) open |= 1u << k;
  }
  if (!open) return;
  // Nothing to prune without choices; nothing to simplify for leaves that do not use their tape.
  bool leaf_tape = true;
  if constexpr (requires { Visitor::leaf_tape(); }) leaf_tape = Visitor::leaf_tape();
  const bool reuse = t.choice_count() == 0 || (last && !leaf_tape);
  // A child that keeps most of a big parent uses the parent (valid in the child's box): writing
  // a copy of millions of instructions costs more than evaluating the rest (converted meshes at
  // the coarse levels).
  const bool parent_serves = t.size() >= kBigTape;
  if (t.size() >= kBigTape && !reuse)
    for (std::uint32_t bits = open; bits && !w.spare.empty(); bits &= bits - 1) {
      Tape& d = dst[__builtin_ctz(bits)];
      if (d.capacity() >= kBigTape) continue;
      w.spare_size -= w.spare.back().capacity();
      d = std::move(w.spare.back());
      w.spare.pop_back();
    }
  const float cap = options_.lipschitz > 0 ? kExactValues : options_.value_cap;
  const std::uint32_t built = reuse ? 0 : w.boxes.simplify(t, open, dst, parent_serves ? kMaxKept : 1.0, last, cap);
  for (std::uint32_t bits = open; bits; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    const Tape* child = built >> k & 1 ? &dst[k] : &t;
    next(Item{boxes[k], child});
    // A big child's tape goes back once it is done with (its buffers would otherwise stay at
    // their high-water mark in this slot for the rest of the run): to the worker's spares while
    // they have room.
    if (release && child == &dst[k] && dst[k].size() >= kBigTape) {
      if (w.spare_size + dst[k].capacity() <= kSpareInstructions) {
        w.spare_size += dst[k].capacity();
        w.spare.push_back(std::move(dst[k]));
      }
      dst[k] = Tape();
    }
  }
}

template <class Visitor, class Outs, class Next>
void Subdivider::split(Worker& w, const Tape& t, const SampleGrid& grid, int level, const IndexBox& parent,
                       Visitor& v, int worker, Outs&& outs, Next&& next) {
  const int step = options_.tiles[static_cast<std::size_t>(level)];
  const bool last = level + 1 == static_cast<int>(options_.tiles.size());
  const int lanes = group_lanes(t);
  IndexBox boxes[kLanes];
  int count = 0, group = 0;
  auto flush = [&] {
    settle(w, t, grid, last, boxes, count, v, worker, outs(group), next);
    count = 0;
    ++group;
  };
  for_each_child(parent, step, [&](const IndexBox& b) {
    if constexpr (requires { v.skip(worker, b); }) {
      if (v.skip(worker, b)) return;
    }
    boxes[count] = b;
    if (++count == lanes) flush();
  });
  if (count) flush();
}

template <class Visitor>
std::vector<Subdivider::Item> Subdivider::split_among_workers(const std::vector<Item>& frontier, const SampleGrid& grid,
                                                              int level, int levels, Visitor& v,
                                                              std::vector<Tape>& store) {
  const int step = options_.tiles[static_cast<std::size_t>(level)];
  const bool last = level + 1 == levels;
  struct Group {
    const Tape* tape;
    int count = 0;
    IndexBox boxes[kLanes];
  };
  std::vector<Group> groups;
  for (const Item& it : frontier) {
    // The children in split()'s order; skipped ones dropped here, on the calling worker (0).
    std::vector<IndexBox> children;
    for_each_child(it.box, step, [&](const IndexBox& b) {
      if constexpr (requires { v.skip(0, b); }) {
        if (v.skip(0, b)) return;
      }
      children.push_back(b);
    });
    const std::size_t share = (children.size() * frontier.size() + static_cast<std::size_t>(workers()) - 1) /
                              static_cast<std::size_t>(workers());
    const std::size_t lanes = std::clamp<std::size_t>(share, 1, static_cast<std::size_t>(group_lanes(*it.tape)));
    for (std::size_t c = 0; c < children.size(); ++c) {
      if (c % lanes == 0) groups.emplace_back().tape = it.tape;
      Group& g = groups.back();
      g.boxes[g.count++] = children[c];
    }
  }
  if (store.size() < groups.size() * kLanes) store.resize(groups.size() * kLanes);
  std::vector<std::vector<Item>> parts(groups.size());
  pool_->parallel_for(static_cast<int>(groups.size()), [&](int wi, int gi) {
    Worker& w = *workers_[static_cast<std::size_t>(wi)];
    const Group& g = groups[static_cast<std::size_t>(gi)];
    std::vector<Item>& out = parts[static_cast<std::size_t>(gi)];
    settle(w, *g.tape, grid, last, g.boxes, g.count, v, wi, &store[static_cast<std::size_t>(gi) * kLanes],
           [&](const Item& child) {
             if (last) v.leaf(wi, *child.tape, child.box);
             else out.push_back(child);
           },
           /*release=*/last);
  });
  std::vector<Item> open;
  for (auto& p : parts) open.insert(open.end(), p.begin(), p.end());
  return open;
}

template <class Visitor>
void Subdivider::run(const Tape& tape, const SampleGrid& grid, const IndexBox& region, Visitor& v) {
  FREP_ASSERT(tape.size() > 0, "empty tape");
  for (int a = 0; a < 3; ++a) {
    FREP_ASSERT(region.lo[a] >= 0 && region.hi[a] <= grid.count(a), "region outside the grid");
    if (region.lo[a] >= region.hi[a]) return;
  }
  const int levels = static_cast<int>(options_.tiles.size());
  for (auto& w : workers_)
    if (static_cast<int>(w->tapes.size()) < levels) w->tapes.resize(static_cast<std::size_t>(levels));

  // Depth first below the parallel frontier; recursion depth is the number of levels.
  auto descend = [&](auto&& self, int wi, const Item& item, int level) -> void {
    if (level + 1 == levels) return v.leaf(wi, *item.tape, item.box);
    Worker& w = *workers_[static_cast<std::size_t>(wi)];
    split(w, *item.tape, grid, level + 1, item.box, v, wi,
          [&](int) { return w.tapes[static_cast<std::size_t>(level + 1)].data(); },
          [&](const Item& child) { self(self, wi, child, level + 1); });
  };

  // Big tapes (converted meshes) never go breadth first: a frontier would keep a simplified
  // tape of up to millions of instructions for every open box of its levels.
  if (options_.breadth_first_levels <= 0 || tape.size() >= kBigTape) {
    // Boxes of the first level, or of the first level with enough of them for the workers to
    // share (the work of a big tape sits in a few boxes), each on its own from the whole tape:
    // split() over a parent that is the box itself. Listed level by level within their parents,
    // so they are exactly the boxes a descent would make.
    std::vector<IndexBox> top{region};
    int start = -1;
    while (start + 1 < levels && (start < 0 || top.size() < static_cast<std::size_t>(4 * workers()))) {
      const int step = options_.tiles[static_cast<std::size_t>(++start)];
      std::vector<IndexBox> next;
      for (const IndexBox& p : top)
        for_each_child(p, step, [&](const IndexBox& b) { next.push_back(b); });
      top = std::move(next);
    }
    // The top boxes in groups, each group in one interval pass on the whole tape; then the open
    // ones descend in parallel, each from its own simplified tape.
    const bool last = start + 1 == levels;
    // At least one group per worker: a single group would leave the other workers idle while
    // the whole tape is evaluated and simplified for the top boxes.
    const std::size_t per_worker = (top.size() + static_cast<std::size_t>(workers()) - 1) / static_cast<std::size_t>(workers());
    const std::size_t lanes = std::min(static_cast<std::size_t>(group_lanes(tape)), std::max<std::size_t>(per_worker, 1));
    const std::size_t groups = (top.size() + lanes - 1) / lanes;
    if (frontier_tapes_.empty()) frontier_tapes_.resize(1);
    std::vector<Tape>& store = frontier_tapes_[0];
    if (store.size() < groups * kLanes) store.resize(groups * kLanes);
    std::vector<std::vector<Item>> parts(groups);
    pool_->parallel_for(static_cast<int>(groups), [&](int wi, int g) {
      Worker& w = *workers_[static_cast<std::size_t>(wi)];
      const std::size_t gi = static_cast<std::size_t>(g);
      IndexBox boxes[kLanes];
      int count = 0;
      for (std::size_t i = gi * lanes; i < std::min(top.size(), (gi + 1) * lanes); ++i) {
        if constexpr (requires { v.skip(wi, top[i]); }) {
          if (v.skip(wi, top[i])) continue;
        }
        boxes[count++] = top[i];
      }
      if (!count) return;
      settle(w, tape, grid, last, boxes, count, v, wi, &store[gi * kLanes], [&](const Item& child) {
        if (last) v.leaf(wi, *child.tape, child.box);
        else parts[gi].push_back(child);
      }, /*release=*/last);
    });
    if (!last) {
      std::vector<Item> items;
      for (auto& p : parts) items.insert(items.end(), p.begin(), p.end());
      pool_->parallel_for(static_cast<int>(items.size()),
                          [&](int wi, int i) { descend(descend, wi, items[static_cast<std::size_t>(i)], start); });
    }
    for (Tape& t : store)
      if (t.size() >= kBigTape) t = Tape();
    return;
  }

  // Breadth first for the first levels, so that the parallel work items are many and small
  // enough to balance. Simplified tapes of the frontier are kept per level.
  // Beyond the levels asked for, breadth first goes on while the frontier is too small for the
  // workers to share (a view volume just over a power of two splits into 2 boxes at the top,
  // leaving one worker all the work).
  const int asked = std::clamp(options_.breadth_first_levels, 1, levels);
  const std::size_t enough = workers() > 1 ? static_cast<std::size_t>(4 * workers()) : 1;
  if (static_cast<int>(frontier_tapes_.size()) < levels) frontier_tapes_.resize(static_cast<std::size_t>(levels));
  std::vector<Item> frontier{{region, &tape}};
  int level = 0;  // after the loop: the number of levels expanded breadth first
  for (; level < levels && (level < asked || frontier.size() < enough); ++level) {
    std::vector<Tape>& store = frontier_tapes_[static_cast<std::size_t>(level)];
    if (frontier.size() < static_cast<std::size_t>(workers())) {
      // Fewer boxes than workers (the top of the region): their children are shared out in
      // smaller groups, so that the workers do not wait for one of them to run a group's
      // interval pass and simplification on the whole tape alone. The boxes a group holds do
      // not change what is computed for each.
      frontier = split_among_workers(frontier, grid, level, levels, v, store);
      continue;
    }
    const int step = options_.tiles[static_cast<std::size_t>(level)];
    // Tape slots per frontier box: kLanes per group of children.
    std::vector<std::size_t> first(frontier.size() + 1, 0);
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      const Item& it = frontier[i];
      std::size_t c = 1;
      for (int a = 0; a < 3; ++a) c *= static_cast<std::size_t>((it.box.extent(a) + step - 1) / step);
      const std::size_t lanes = static_cast<std::size_t>(group_lanes(*it.tape));
      first[i + 1] = first[i] + (c + lanes - 1) / lanes * kLanes;
    }
    if (store.size() < first.back()) store.resize(first.back());
    std::vector<std::vector<Item>> parts(frontier.size());
    pool_->parallel_for(static_cast<int>(frontier.size()), [&](int wi, int i) {
      Worker& w = *workers_[static_cast<std::size_t>(wi)];
      const Item& it = frontier[static_cast<std::size_t>(i)];
      std::vector<Item>& out = parts[static_cast<std::size_t>(i)];
      auto keep = [&](const Item& child) { out.push_back(child); };
      auto tapes = [&](int g) { return &store[first[static_cast<std::size_t>(i)] + static_cast<std::size_t>(g) * kLanes]; };
      if (level + 1 == levels) {
        // The frontier is the last level: its boxes are leaves.
        split(w, *it.tape, grid, level, it.box, v, wi, tapes, [&](const Item& child) { v.leaf(wi, *child.tape, child.box); });
      } else {
        split(w, *it.tape, grid, level, it.box, v, wi, tapes, keep);
      }
    });
    frontier.clear();
    for (auto& p : parts) frontier.insert(frontier.end(), p.begin(), p.end());
  }
  if (level == levels) return;
  pool_->parallel_for(static_cast<int>(frontier.size()),
                      [&](int wi, int i) { descend(descend, wi, frontier[static_cast<std::size_t>(i)], level - 1); });
}

}  // namespace frep
