// The subdivision driver: every sample of the grid is covered exactly once, by a settled box or a
// leaf; each leaf's tape gives the whole tape's values at the leaf's samples, bit for bit; and the
// leaves it reaches are the same for every thread count and breadth-first setting (0: boxes in
// parallel from the whole tape), also for tapes big enough to take the driver's
// big-tape paths (fewer boxes per group, children reusing their parent). With a Lipschitz bound,
// every box settled by its centre's value has the settled sign at every one of its samples, and
// fewer boxes reach the leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <tuple>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/subdivision.hpp"
#include "frep/expr/expr.hpp"

namespace frep {
namespace {

// A union of n small spheres scattered in [-1, 0] x [-1, 1]^2 (a tape of about 10 n
// instructions; boxes with x > 0 settle).
// With `expanded`, each distance is written as sqrt(|p|^2 - 2 p.c + |c|^2): the same function,
// whose intervals are much wider (x appears twice).
Tape spheres(Graph& g, int n, unsigned seed, bool expanded = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), h(-1.0f, 0.0f);
  std::vector<Expr> terms;
  for (int i = 0; i < n; ++i) {
    const float cx = h(rng), cy = u(rng), cz = u(rng);
    if (expanded)
      terms.push_back(sqrt(max(square(g.x()) + square(g.y()) + square(g.z()) - 2.0f * (cx * g.x() + cy * g.y() + cz * g.z()) +
                               (cx * cx + cy * cy + cz * cz), 0.0f)) - 0.05f);
    else
      terms.push_back(sqrt(square(g.x() - cx) + square(g.y() - cy) + square(g.z() - cz)) - 0.05f);
  }
  while (terms.size() > 1) {
    std::vector<Expr> next;
    for (std::size_t i = 0; i + 1 < terms.size(); i += 2) next.push_back(min(terms[i], terms[i + 1]));
    if (terms.size() % 2) next.push_back(terms.back());
    terms = next;
  }
  return Tape::compile(g, terms[0].id());
}

SampleGrid grid(int n) {
  SampleGrid s;
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < n; ++i) s.coords[a].push_back(-1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(n - 1));
  return s;
}

// The values of `tape` at the grid's samples in box b (x fastest, then y, then z).
std::vector<float> values_in(BatchEvaluator& eval, const Tape& tape, const SampleGrid& grid, const IndexBox& b) {
  std::vector<float> xs, ys, zs;
  for (int z = b.lo[2]; z < b.hi[2]; ++z)
    for (int y = b.lo[1]; y < b.hi[1]; ++y)
      for (int x = b.lo[0]; x < b.hi[0]; ++x) {
        xs.push_back(grid.coords[0][static_cast<std::size_t>(x)]);
        ys.push_back(grid.coords[1][static_cast<std::size_t>(y)]);
        zs.push_back(grid.coords[2][static_cast<std::size_t>(z)]);
      }
  std::vector<float> out(xs.size());
  eval.eval(tape, xs.data(), ys.data(), zs.data(), out.data(), xs.size());
  return out;
}

struct Recorder {
  const Tape& whole;
  const SampleGrid& grid;
  std::mutex m;
  std::set<std::tuple<int, int, int, int, int, int, bool>> boxes;  // lo, hi, leaf
  std::vector<int> covered;
  std::map<std::tuple<int, int, int>, std::vector<float>>& whole_values;  // per leaf, shared by runs
  std::string mismatch;
  BatchEvaluator eval_leaf, eval_whole;

  Recorder(const Tape& t, const SampleGrid& g, std::map<std::tuple<int, int, int>, std::vector<float>>& cache)
      : whole(t), grid(g), covered(static_cast<std::size_t>(g.count(0) * g.count(1) * g.count(2)), 0), whole_values(cache) {}
  void cover(const IndexBox& b) {
    for (int z = b.lo[2]; z < b.hi[2]; ++z)
      for (int y = b.lo[1]; y < b.hi[1]; ++y)
        for (int x = b.lo[0]; x < b.hi[0]; ++x) ++covered[static_cast<std::size_t>((z * grid.count(1) + y) * grid.count(0) + x)];
  }
  bool settled(int, const IndexBox& b, Interval v) {
    if (!(v.lo > 0 || v.hi < 0)) return false;
    std::lock_guard<std::mutex> l(m);
    boxes.insert({b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2], false});
    cover(b);
    return true;
  }
  void leaf(int, const Tape& t, const IndexBox& b) {
    std::lock_guard<std::mutex> l(m);
    boxes.insert({b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2], true});
    cover(b);
    // The leaf's corners: its tape against the whole tape.
    std::vector<float> xs, ys, zs;
    for (int z : {b.lo[2], b.hi[2] - 1})
      for (int y : {b.lo[1], b.hi[1] - 1})
        for (int x : {b.lo[0], b.hi[0] - 1}) {
          xs.push_back(grid.coords[0][static_cast<std::size_t>(x)]);
          ys.push_back(grid.coords[1][static_cast<std::size_t>(y)]);
          zs.push_back(grid.coords[2][static_cast<std::size_t>(z)]);
        }
    std::vector<float> a(xs.size());
    eval_leaf.eval(t, xs.data(), ys.data(), zs.data(), a.data(), xs.size());
    std::vector<float>& w = whole_values[{b.lo[0], b.lo[1], b.lo[2]}];
    if (w.empty()) {
      w.resize(xs.size());
      eval_whole.eval(whole, xs.data(), ys.data(), zs.data(), w.data(), xs.size());
    }
    for (std::size_t i = 0; i < a.size(); ++i)
      if (std::memcmp(&a[i], &w[i], sizeof(float)) != 0 && mismatch.empty())
        mismatch = "leaf at " + std::to_string(b.lo[0]) + "," + std::to_string(b.lo[1]) + "," + std::to_string(b.lo[2]);
  }
};

void check(int spheres_count, int n, std::vector<int> tiles) {
  Graph g;
  const Tape t = spheres(g, spheres_count, 7);
  const SampleGrid s = grid(n);
  std::set<std::tuple<int, int, int, int, int, int, bool>> reference;
  std::map<std::tuple<int, int, int>, std::vector<float>> cache;
  bool settled_any = false;
  for (int bfs : {0, 1, 2})
    for (int threads : {1, 2}) {
      SCOPED_TRACE("tape " + std::to_string(t.size()) + ", breadth first " + std::to_string(bfs) + ", threads " +
                   std::to_string(threads));
      Subdivider d({tiles, threads, bfs});
      Recorder r(t, s, cache);
      d.run(t, s, r);
      EXPECT_EQ(r.mismatch, "");
      EXPECT_TRUE(std::all_of(r.covered.begin(), r.covered.end(), [](int c) { return c == 1; }));
      // The leaves are the same boxes whatever the setting (settled boxes may come whole or as
      // their children: without a frontier, parallel work starts at a finer level).
      std::set<std::tuple<int, int, int, int, int, int, bool>> leaves;
      for (const auto& b : r.boxes)
        if (std::get<6>(b)) leaves.insert(b);
      if (reference.empty()) reference = leaves;
      EXPECT_EQ(leaves, reference);
      settled_any |= leaves.size() < r.boxes.size();
    }
  // Something was settled and something reached the leaves.
  EXPECT_GT(reference.size(), 0u);
  EXPECT_TRUE(settled_any);
}

TEST(Subdivision, SmallTapeCoversEveryBoxOnceWithExactLeafTapes) { check(40, 48, {16, 8, 4}); }

// A top tile as big as the grid: one box at the first level, too few for two workers, so the
// frontier goes on breadth first past the levels asked for (the same leaves either way).
TEST(Subdivision, SmallFrontierGoesOnBreadthFirst) { check(40, 48, {64, 16, 4}); }

// Above the driver's big-tape threshold (2^18 instructions).
TEST(Subdivision, BigTapeTakesTheSameBoxes) { check(30000, 24, {12, 6, 3}); }

// The union of spheres is an exact distance outside and 1-Lipschitz everywhere (up to the
// rounding of the expanded form, far below the driver's slack).
void check_lipschitz(int spheres_count, int n, std::vector<int> tiles) {
  Graph g;
  const Tape t = spheres(g, spheres_count, 11, true);
  const SampleGrid s = grid(n);
  std::map<std::tuple<int, int, int>, std::vector<float>> cache;
  std::size_t leaves_without = 0;
  for (double lipschitz : {0.0, 1.0})
    for (int threads : {1, 2}) {
      SCOPED_TRACE("Lipschitz " + std::to_string(lipschitz) + ", threads " + std::to_string(threads));
      SubdivisionOptions o{tiles, threads, 0};
      o.lipschitz = lipschitz;
      Subdivider d(o);
      struct Checker : Recorder {
        using Recorder::Recorder;
        BatchEvaluator eval;
        std::string wrong;
        bool settled(int w, const IndexBox& b, Interval v) {
          if (!Recorder::settled(w, b, v)) return false;
          std::lock_guard<std::mutex> l(m);
          for (float f : values_in(eval, whole, grid, b))
            if (!(f >= v.lo && f <= v.hi) && wrong.empty())
              wrong = "box at " + std::to_string(b.lo[0]) + "," + std::to_string(b.lo[1]) + "," + std::to_string(b.lo[2]) +
                      " settled with [" + std::to_string(v.lo) + ", " + std::to_string(v.hi) + "] has a sample of " +
                      std::to_string(f);
          return true;
        }
      } r(t, s, cache);
      d.run(t, s, r);
      EXPECT_EQ(r.mismatch, "");
      EXPECT_EQ(r.wrong, "");
      EXPECT_TRUE(std::all_of(r.covered.begin(), r.covered.end(), [](int c) { return c == 1; }));
      std::size_t leaves = 0;
      for (const auto& b : r.boxes) leaves += std::get<6>(b);
      if (lipschitz == 0) leaves_without = leaves;
      else EXPECT_LT(leaves, leaves_without) << "the centre's value settles more boxes";
    }
}

TEST(Subdivision, LipschitzBoundSettlesBoxesByTheirCentre) { check_lipschitz(40, 48, {16, 8, 4}); }
TEST(Subdivision, LipschitzBoundOnABigTape) { check_lipschitz(20000, 16, {8, 4, 2}); }

// A visitor that reads only signs sets value_cap = 0: boxes settle on signs, and leaf tapes must
// give the whole tape's sign at every sample (its value where that is <= 0). They are shorter
// than exact leaf tapes: far spheres go even where no sphere lies below them. With a Lipschitz
// bound the cap is not used (the same leaf tapes as without it).
TEST(Subdivision, SignCapKeepsSignsAndShortensLeafTapes) {
  Graph g;
  const Tape t = spheres(g, 60, 12);
  const SampleGrid s = grid(40);
  struct SignChecker {
    SignChecker(const Tape& t, const SampleGrid& g) : whole(t), grid(g) {}
    const Tape& whole;
    const SampleGrid& grid;
    std::mutex m;
    BatchEvaluator eval;
    std::size_t leaf_instructions = 0, samples = 0;
    std::string wrong;
    std::vector<float> values(const Tape& tape, const IndexBox& b) { return values_in(eval, tape, grid, b); }
    bool settled(int, const IndexBox& b, Interval v) {
      if (!(v.hi < 0) && !(v.lo >= 0)) return false;
      std::lock_guard<std::mutex> l(m);
      for (float f : values(whole, b))
        if ((f < 0) != (v.hi < 0) && wrong.empty()) wrong = "a settled box has a sample of the other sign";
      return true;
    }
    void leaf(int, const Tape& tape, const IndexBox& b) {
      std::lock_guard<std::mutex> l(m);
      const std::vector<float> want = values(whole, b), got = values(tape, b);
      leaf_instructions += tape.size();
      samples += want.size();
      for (std::size_t i = 0; i < want.size(); ++i) {
        const bool ok = want[i] > 0 ? got[i] > 0 : std::memcmp(&want[i], &got[i], sizeof(float)) == 0;
        if (!ok && wrong.empty()) wrong = "a leaf tape gives " + std::to_string(got[i]) + " for " + std::to_string(want[i]);
      }
    }
  };
  std::size_t exact = 0;
  for (double lipschitz : {0.0, 1.0})
    for (float cap : {kExactValues, 0.0f})
      for (int threads : {1, 2}) {
        SCOPED_TRACE("cap " + std::to_string(cap) + ", Lipschitz " + std::to_string(lipschitz) + ", threads " +
                     std::to_string(threads));
        SubdivisionOptions o{{16, 8, 4}, threads, 0};
        o.lipschitz = lipschitz;
        o.value_cap = cap;
        Subdivider d(o);
        SignChecker c(t, s);
        d.run(t, s, c);
        EXPECT_EQ(c.wrong, "");
        EXPECT_GT(c.samples, 0u);
        if (cap == kExactValues) exact = c.leaf_instructions;
        else if (lipschitz == 0) EXPECT_LT(c.leaf_instructions, exact * 3 / 4) << "the sign cap should drop far spheres";
        else EXPECT_EQ(c.leaf_instructions, exact) << "no cap with a Lipschitz bound";
      }
}

// lipschitz_bound narrows an interval to f(c) +- L r, rounded outward, and never widens it.
TEST(Subdivision, LipschitzBoundNarrowsOnlyWithinTheBox) {
  const Interval box{-5, 7};
  const Interval n = lipschitz_bound(box, Interval::point(2), 1.0, 1.5, 1.0);
  EXPECT_LT(n.lo, 0.5f);
  EXPECT_GT(n.lo, 0.49f);
  EXPECT_GT(n.hi, 3.5f);
  EXPECT_LT(n.hi, 3.51f);
  EXPECT_EQ(lipschitz_bound(box, Interval::point(2), 1.0, 100, 1.0).lo, box.lo);  // never wider
  EXPECT_EQ(lipschitz_bound(box, Interval::point(2), 0.0, 1.5, 1.0).hi, box.hi);  // unknown: as it was
  const Interval unknown = lipschitz_bound(box, Interval::unknown(), 1.0, 1.5, 1.0);
  EXPECT_EQ(unknown.lo, box.lo);
  // A centre value far outside the box's interval (not a Lipschitz field): what intervals proved.
  const Interval bad = lipschitz_bound(box, Interval::point(100), 1.0, 1.0, 1.0);
  EXPECT_EQ(bad.lo, box.lo);
  EXPECT_EQ(bad.hi, box.hi);
}

}  // namespace
}  // namespace frep
