// Pruning: a tape simplified over a box must give bit-identical point values (or NaN where the
// full tape gives NaN) everywhere inside that box, must not be longer than the original, and
// must stay right when re-simplified while subdividing.
#include <gtest/gtest.h>

#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/expr/expr.hpp"
#include "frep/io/vm.hpp"
#include "test_util.hpp"

namespace frep {
namespace {

using test::Box;
using test::fstr;
using test::istr;
using test::same_value;

class SimplifyChecker {
 public:
  // With a finite `cap`, tapes are simplified with that root cap (Tape::simplify): they must give
  // full_'s values where those are <= cap (or NaN), and values > cap where full_'s are.
  SimplifyChecker(const Tape& full, std::mt19937_64& rng, float cap = kExactValues) : full_(full), rng_(rng), cap_(cap) {}

  // Simplifies `tape` (a simplification of full_, or full_ itself) over `box`, checks the result
  // against full_ at points inside the box, and recurses into sub-boxes down to `depth` levels.
  void run(const Tape& tape, const Box& box, int depth, int points) {
    IntervalEvaluator ie;
    ie.eval(tape, box.x, box.y, box.z);
    const std::vector<Interval> iv(ie.values().begin(), ie.values().begin() + tape.size());
    Tape s;
    tape.simplify(ie.values(), ie.choices(), s, true, cap_);
    ++simplified_;
    EXPECT_LE(s.size(), tape.size());
    EXPECT_LE(s.choice_count(), tape.choice_count());
    Tape exact;
    tape.simplify(ie.values(), ie.choices(), exact);
    // (Not always shorter: where exact simplification aliases a min to one side, the capped one
    // may write a constant above the cap instead, one instruction more.)
    if (s.size() < exact.size()) ++shorter_than_exact_;
    if (cap_ == kExactValues) {
      // The other entry point gives the same tape.
      Tape s2;
      IntervalEvaluator ie2;
      ie2.simplify(tape, box.x, box.y, box.z, s2);
      EXPECT_EQ(s2.size(), s.size());
    }
    if (s.size() < tape.size()) ++shorter_;

    // Exact where the full tape is <= cap (or NaN), above the cap where it is above.
    const auto agrees = [&](float got, float want) { return want > cap_ ? got > cap_ : same_value(got, want); };
    for (const test::Point3& p : test::points_in(box, rng_, points)) {
      const float want = pe_.eval(full_, p.x, p.y, p.z);
      const float parent = pe_.eval(tape, p.x, p.y, p.z);
      const float got = pe_.eval(s, p.x, p.y, p.z);
      ++checked_;
      if (!agrees(got, want) || !agrees(parent, want)) {
        ADD_FAILURE() << "simplified over x" << istr(box.x) << " y" << istr(box.y) << " z" << istr(box.z)
                      << " (depth " << depth << "): at (" << fstr(p.x) << ", " << fstr(p.y) << ", " << fstr(p.z)
                      << ") the full tape gives " << fstr(want) << ", the parent " << fstr(parent)
                      << ", the simplified tape " << fstr(got) << " (sizes " << full_.size() << " / "
                      << tape.size() << " / " << s.size() << ")";
        failed_ = true;
        return;
      }
    }
    if (depth <= 0 || failed_) return;
    // Two random sub-boxes, one of them tiny.
    for (int k = 0; k < 2; ++k) {
      Box sub;
      auto shrink = [&](Interval i) {
        if (!(std::isfinite(i.lo) && std::isfinite(i.hi)) || i.lo == i.hi) return i;
        const double f = k == 0 ? 0.5 : 0.05;
        const double w = (static_cast<double>(i.hi) - i.lo) * f;
        const double lo = i.lo + (static_cast<double>(i.hi) - i.lo - w) * std::uniform_real_distribution<double>(0, 1)(rng_);
        float a = static_cast<float>(lo), b = static_cast<float>(lo + w);
        a = std::max(a, i.lo), b = std::min(b, i.hi);
        return a <= b ? Interval{a, b} : i;
      };
      sub.x = shrink(box.x), sub.y = shrink(box.y), sub.z = shrink(box.z);
      run(s, sub, depth - 1, points);
    }
  }

  int simplified_ = 0, shorter_ = 0, shorter_than_exact_ = 0;
  long checked_ = 0;
  bool failed_ = false;

 private:
  const Tape& full_;
  std::mt19937_64& rng_;
  float cap_;
  PointEvaluator pe_;
};

Box everyday_box(std::mt19937_64& rng, float range) {
  auto iv = [&] {
    const float c = std::uniform_real_distribution<float>(-range, range)(rng);
    const float w = std::pow(10.0f, std::uniform_real_distribution<float>(-6, 0.3f)(rng));
    return Interval{c - w, c + w};
  };
  return {iv(), iv(), iv()};
}

TEST(Simplify, RandomChoiceHeavyExpressionsWhileSubdividing) {
  std::mt19937_64 rng(41);
  long checked = 0;
  int simplified = 0, shorter = 0;
  for (int e = 0; e < 400; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 5 + e % 4;
    opt.ops = {Op::Min, Op::Max, Op::And, Op::Or, Op::Min, Op::Max, Op::And, Op::Or, Op::Min, Op::Max,
               Op::Add, Op::Sub, Op::Mul, Op::Neg, Op::Abs, Op::Square, Op::Sqrt, Op::Compare, Op::Not,
               Op::Sin, Op::Floor, Op::Div, Op::Mod, Op::Exp, Op::Atan, Op::Round, Op::Recip, Op::Ln};
    opt.special_const_prob = e % 3 == 0 ? 0.1 : 0.0;
    test::ExprGen gen(g, rng, opt);
    const Tape t = Tape::compile(g, gen.gen());
    SimplifyChecker c(t, rng);
    for (int b = 0; b < 4 && !c.failed_; ++b) {
      const Box box = b == 3 ? Box{test::random_interval(rng), test::random_interval(rng), test::random_interval(rng)}
                             : everyday_box(rng, 3);
      c.run(t, box, 3, 10);
    }
    checked += c.checked_, simplified += c.simplified_, shorter += c.shorter_;
    if (c.failed_) FAIL() << "expression #" << e << " failed";
  }
  EXPECT_GT(checked, 50000);
  EXPECT_GT(shorter, simplified / 20) << "simplification almost never shortens choice-heavy tapes";
}

// A root cap C (what a sign-only consumer passes, C = 0): values <= C stay exact, values above
// only stay above, through repeated simplification while subdividing; and it drops terms exact
// simplification cannot (a union's terms that are only positive in the box).
TEST(Simplify, RootCapKeepsValuesUpToItAndOnlyWhichSideAbove) {
  std::mt19937_64 rng(2026);
  long checked = 0;
  int simplified = 0, shorter_than_exact = 0;
  for (int e = 0; e < 300; ++e) {
    Graph g;
    test::GenOptions opt;
    opt.max_depth = 4 + e % 4;
    opt.ops = {Op::Min, Op::Max, Op::Min, Op::Max, Op::Min, Op::Max, Op::And, Op::Or, Op::Add, Op::Sub,
               Op::Mul, Op::Neg, Op::Abs, Op::Square, Op::Sqrt, Op::Compare, Op::Sin, Op::Div, Op::Exp};
    opt.special_const_prob = e % 3 == 0 ? 0.1 : 0.0;
    test::ExprGen gen(g, rng, opt);
    // A union or intersection at the root, the shape of a CSG model (only a min or max reads a cap).
    const NodeId a = gen.gen(), b = gen.gen();
    const Tape t = Tape::compile(g, g.binary(e % 2 ? Op::Min : Op::Max, a, b));
    const float cap = e % 4 == 0 ? std::uniform_real_distribution<float>(-2, 2)(rng) : 0.0f;
    SimplifyChecker c(t, rng, cap);
    for (int k = 0; k < 4 && !c.failed_; ++k) {
      const Box box = k == 3 ? Box{test::random_interval(rng), test::random_interval(rng), test::random_interval(rng)}
                             : everyday_box(rng, 3);
      c.run(t, box, 3, 10);
    }
    checked += c.checked_, simplified += c.simplified_, shorter_than_exact += c.shorter_than_exact_;
    if (c.failed_) FAIL() << "expression #" << e << " (cap " << cap << ") failed";
  }
  EXPECT_GT(checked, 40000);
  EXPECT_GT(shorter_than_exact, simplified / 100) << "a root cap should drop more than exact simplification";
}

TEST(Simplify, SelectsAndPiecewiseFunctions) {
  Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  // x >= 0 ? box : sphere, built from and/or/not/compare like the converter does.
  auto inside = compare(x, g.c(0)) + 1.0f;  // 0 where x < 0, non-zero elsewhere
  auto f = if_nonzero_else(inside, max(abs(x) - 1, abs(y) - 1), sqrt(square(x) + square(y) + square(z)) - 1);
  const Tape t = Tape::compile(g, f.id());
  std::mt19937_64 rng(42);
  SimplifyChecker c(t, rng);
  c.run(t, {{-2, -1}, {-1, 1}, {0, 0}}, 4, 30);
  c.run(t, {{1, 2}, {-1, 1}, {-0.5f, 0.5f}}, 4, 30);
  c.run(t, {{-1, 1}, {-1, 1}, {-1, 1}}, 4, 30);
  c.run(t, {{0, 0}, {0.5f, 0.5f}, {0, 0}}, 1, 5);
  c.run(t, {{-0.0f, 0.0f}, {-3, 3}, {0, 0}}, 2, 10);
  EXPECT_FALSE(c.failed_);
  // On x > 0 only the box part remains: no sqrt.
  IntervalEvaluator ie;
  Tape s;
  ie.simplify(t, {1, 2}, {-1, 1}, {0, 0}, s);
  for (const SsaInstr& ins : s.ssa()) EXPECT_NE(ins.op, Op::Sqrt);
  EXPECT_LT(s.size(), t.size());
}

TEST(Simplify, ConstantAndVariableRoots) {
  Graph g;
  auto x = g.x(), y = g.y();
  IntervalEvaluator ie;
  PointEvaluator pe;
  // min(x, y + 10) on x in [0, 1] is x: the simplified root is a variable.
  Tape s;
  const Tape t = Tape::compile(g, min(x, y + 10.0f).id());
  ie.simplify(t, {0, 1}, {0, 1}, {0, 0}, s);
  EXPECT_EQ(s.size(), 1u);
  EXPECT_EQ(pe.eval(s, 0.5f, 0.25f, 0), 0.5f);
  // compare over disjoint intervals folds to a constant.
  const Tape t2 = Tape::compile(g, (compare(x, y) * x).id());
  ie.simplify(t2, {0, 1}, {2, 3}, {0, 0}, s);
  EXPECT_EQ(pe.eval(s, 0.5f, 2.5f, 0), -0.5f);
  EXPECT_LT(s.size(), t2.size());
  // Re-simplifying the simplified tape into another tape object repeatedly keeps working.
  Tape a, b;
  ie.simplify(t, {-1, 1}, {-1, 1}, {0, 0}, a);
  for (int i = 0; i < 10; ++i) {
    ie.simplify(a, {-1, 1}, {-1, 1}, {0, 0}, b);
    std::swap(a, b);
    EXPECT_EQ(pe.eval(a, 0.25f, -0.5f, 0), pe.eval(t, 0.25f, -0.5f, 0));
  }
}

// Caps (eval/caps.hpp): in min(min(a, c), b), `a` overlaps its sibling c but starts above b
// everywhere, so it goes; through a max, and in the 16-box pass alike. A value that another,
// uncapped use needs exactly stays.
TEST(Simplify, CapsDropMinTermsBeyondTheNearestAnywhereInTheTree) {
  Graph g;
  auto x = g.x();
  const Expr a = x + 10.0f, c = x * 100.0f, b = x;
  const Expr root = max(min(min(a, c), b), -5.0f);
  const Tape t = Tape::compile(g, root.id());
  const Tape want = Tape::compile(g, min(c, b).id());  // the max goes too: its left side is >= 0
  IntervalEvaluator ie;
  PointEvaluator pe;
  Tape s;
  ie.simplify(t, {0, 1}, {0, 0}, {0, 0}, s);
  EXPECT_EQ(s.size(), want.size());
  IntervalBatchEvaluator batch;
  const Interval xs[2] = {{0, 1}, {0.25f, 0.5f}}, zero[2] = {{0, 0}, {0, 0}};
  batch.eval(t, xs, zero, zero, 2);
  Tape outs[2];
  EXPECT_EQ(batch.simplify(t, 3u, outs), 3u);
  EXPECT_EQ(outs[0].size(), want.size());
  EXPECT_EQ(outs[1].size(), 1u);  // x alone: b < c over [0.25, 0.5]
  for (float v = 0; v <= 1; v += 0.0625f) {
    EXPECT_EQ(pe.eval(s, v, 0, 0), pe.eval(t, v, 0, 0));
    EXPECT_EQ(pe.eval(outs[0], v, 0, 0), pe.eval(t, v, 0, 0));
  }
  // `a` also added to the root: that use needs it everywhere, and min(a, c) with it.
  const Tape t2 = Tape::compile(g, (min(min(a, c), b) + min(a, c)).id());
  ie.simplify(t2, {0, 1}, {0, 0}, {0, 0}, s);
  EXPECT_EQ(s.size(), t2.size());
  for (float v = 0; v <= 1; v += 0.0625f) EXPECT_EQ(pe.eval(s, v, 0, 0), pe.eval(t2, v, 0, 0));
  // Leaving out boxes that would keep more than a fraction of the tape.
  batch.eval(t2, xs, zero, zero, 2);
  EXPECT_EQ(batch.simplify(t2, 3u, outs, 0.5), 0u);
}

// Regression (9b2043f): max(atan(x + y), 2) over x in [1, inf], y in [-inf, -1] must not be
// pruned to the constant 2, since at (inf, -inf) the full tape gives NaN.
TEST(Simplify, InfiniteEndsDoNotMakeAWrongChoice) {
  Graph g;
  auto x = g.x(), y = g.y();
  const float inf = std::numeric_limits<float>::infinity();
  const Tape t = Tape::compile(g, max(atan(x + y), g.c(2)).id());
  IntervalEvaluator ie;
  Tape s;
  ie.simplify(t, {1, inf}, {-inf, -1}, {0, 0}, s);
  PointEvaluator pe;
  EXPECT_TRUE(same_value(pe.eval(s, inf, -inf, 0), pe.eval(t, inf, -inf, 0)))
      << "full " << fstr(pe.eval(t, inf, -inf, 0)) << ", simplified " << fstr(pe.eval(s, inf, -inf, 0));
}

// Consequence of IntervalRegression.DivisorWithZeroAndInfinity: max(atan(x / y), 2) over
// x in [1, inf], y in [-inf, inf] is pruned to 2, but at (inf, inf) the full tape gives NaN.
TEST(SimplifyRegression, DivByIntervalWithZeroAndInfinity) {
  Graph g;
  auto x = g.x(), y = g.y();
  const float inf = std::numeric_limits<float>::infinity();
  const Tape t = Tape::compile(g, max(atan(x / y), g.c(2)).id());
  IntervalEvaluator ie;
  Tape s;
  ie.simplify(t, {1, inf}, {-inf, inf}, {0, 0}, s);
  PointEvaluator pe;
  EXPECT_TRUE(same_value(pe.eval(s, inf, inf, 0), pe.eval(t, inf, inf, 0)))
      << "full " << fstr(pe.eval(t, inf, inf, 0)) << ", simplified " << fstr(pe.eval(s, inf, inf, 0));
}

void check_model(const std::string& name, bool three_d, int boxes, int depth, int points, double min_shorter,
                 float cap = kExactValues) {
  const Model m = read_vm(test::data_file(name));
  const Tape t = Tape::compile(*m.graph, m.root);
  std::mt19937_64 rng(43);
  SimplifyChecker c(t, rng, cap);
  int small = 0, small_shorter = 0;
  for (int b = 0; b < boxes && !c.failed_; ++b) {
    auto iv = [&](double w) {
      const double lo = std::uniform_real_distribution<double>(-1, 1 - w)(rng);
      return Interval{static_cast<float>(lo), static_cast<float>(lo + w)};
    };
    const double w = std::pow(10.0, std::uniform_real_distribution<double>(-4, 0.3)(rng));
    const Box box{iv(w), iv(w), three_d ? iv(w) : Interval{0, 0}};
    IntervalEvaluator ie;
    Tape s;
    ie.simplify(t, box.x, box.y, box.z, s);
    if (w < 0.05) {
      ++small;
      small_shorter += s.size() < t.size();
    }
    c.run(t, box, depth, points);
  }
  EXPECT_FALSE(c.failed_);
  EXPECT_GE(small_shorter, min_shorter * small) << name << ": small boxes should usually prune the tape";
  if (cap != kExactValues) {
    EXPECT_GT(c.shorter_than_exact_, c.simplified_ / 20) << name << ": the cap should prune more";
  }
}

TEST(Simplify, ProsperoRandomBoxesAndSubdivision) {
  FREP_REQUIRE_DATA("prospero.vm");
  check_model("prospero.vm", false, 40, 4, 6, 0.9);
}

// As a 2D render simplifies it: only signs matter.
TEST(Simplify, ProsperoWithTheSignCap) {
  FREP_REQUIRE_DATA("prospero.vm");
  check_model("prospero.vm", false, 40, 4, 6, 0.9, 0.0f);
}

TEST(Simplify, BearRandomBoxesAndSubdivision) {
  FREP_REQUIRE_DATA("bear.vm");
  check_model("bear.vm", true, 60, 4, 8, 0.5);
}

TEST(Simplify, ProsperoDescentShrinksTheTape) {
  FREP_REQUIRE_DATA("prospero.vm");
  const Model m = read_vm(test::data_file("prospero.vm"));
  const Tape t = Tape::compile(*m.graph, m.root);
  IntervalEvaluator ie;
  PointEvaluator pe;
  std::mt19937_64 rng(44);
  for (int path = 0; path < 6; ++path) {
    Interval x{-1, 1}, y{-1, 1};
    Tape cur = t, next;
    for (int level = 0; level < 8; ++level) {
      ie.simplify(cur, x, y, {0, 0}, next);
      EXPECT_LE(next.size(), cur.size());
      for (int i = 0; i < 8; ++i) {
        const float px = std::uniform_real_distribution<float>(x.lo, x.hi)(rng);
        const float py = std::uniform_real_distribution<float>(y.lo, y.hi)(rng);
        ASSERT_TRUE(same_value(pe.eval(next, px, py, 0), pe.eval(t, px, py, 0)))
            << "level " << level << " at (" << fstr(px) << ", " << fstr(py) << ")";
      }
      std::swap(cur, next);
      const float mx = 0.5f * (x.lo + x.hi), my = 0.5f * (y.lo + y.hi);
      x = (rng() & 1) ? Interval{x.lo, mx} : Interval{mx, x.hi};
      y = (rng() & 1) ? Interval{y.lo, my} : Interval{my, y.hi};
    }
    EXPECT_LT(cur.size(), t.size() / 10) << "a 1/128-wide cell of prospero should need a small fraction of the tape";
  }
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// Register allocation keeps only live values: a balanced tree over 4096 terms needs registers
// for one path down the tree, not one per term, and the code still evaluates to the SSA values.
TEST(Registers, BalancedTreesNeedFewRegisters) {
  // Built depth first, as frep convert builds its trees: the tape computes a subtree, then the
  // next, and only the partial results on the path stay live.
  Graph g;
  const auto tree = [&](auto&& self, int lo, int hi) -> Expr {
    if (hi - lo == 1) return square(g.x() - static_cast<float>(lo) * 0.01f) + square(g.y());
    const int mid = (lo + hi) / 2;
    const Expr a = self(self, lo, mid);
    return min(a, self(self, mid, hi));
  };
  const std::vector<Expr> level{tree(tree, 0, 4096)};
  const Tape t = Tape::compile(g, level[0].id());
  EXPECT_LE(t.num_registers(), 40u);
  PointEvaluator pe;
  for (float x : {-1.0f, 3.3f, 20.0f, 41.0f})
    EXPECT_EQ(pe.eval(t, x, 0.5f, 0), test::eval_ssa<float>(t.ssa(), x, 0.5f, 0.0f)) << x;
}

}  // namespace
}  // namespace frep
